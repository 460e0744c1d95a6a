"""The format migration table: ports renamed to the Modelica Standard Library's names in scenario
and data-set format 2 (`RENAMED`), and `renamed`, the new name of an old one, which messages give.
"""
from __future__ import annotations

__all__ = ["RENAMED", "renamed"]

# {component: {old name: new}}: ports renamed to the Modelica Standard Library's names in scenario
# and data-set format 2 (an old name ending in "." renames every variable under it), which a
# master names when a file uses the old name. An old name that names another variable now (the
# PID's y) is refused in a file that does not declare format 2.
RENAMED: dict[str, dict[str, str]] = {
    "CrawlerBody": {"flange1.": "flange_a.", "flange2.": "flange_b."},
    "PID": {"r": "u_s", "y": "u_m", "u": "y"},
    "GainScheduledPID": {"r": "u_s", "y": "u_m", "u": "y"},
    "BangBang": {"u": "y"}}


def renamed(component: str, variable: str) -> str | None:
    """The name `variable` of `component` has had since format 2 renamed it, or None.

    Examples
    --------
    >>> renamed("CrawlerBody", "flange1.s"), renamed("PID", "y"), renamed("PID", "u_s")
    ('flange_a.s', 'u_m', None)
    """
    for old, new in RENAMED.get(component, {}).items():
        if variable == old or old.endswith(".") and variable.startswith(old):
            return new + variable[len(old):]
    return None

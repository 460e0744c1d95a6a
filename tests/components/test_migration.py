"""The format migration table (components/migration.py): old port names to format 2's."""
import pytest

from musclesim.components import CATALOGUE, RENAMED, declarations, renamed


@pytest.mark.parametrize("component, old, new", [
    ("CrawlerBody", "flange1.s", "flange_a.s"),
    ("CrawlerBody", "flange2.f", "flange_b.f"),
    ("PID", "r", "u_s"), ("PID", "y", "u_m"), ("PID", "u", "y"),
    ("GainScheduledPID", "y", "u_m"), ("BangBang", "u", "y"),
], ids=lambda x: str(x))
def test_an_old_name_gives_its_format_2_name(component, old, new):
    assert renamed(component, old) == new


@pytest.mark.parametrize("component, name", [
    ("CrawlerBody", "flange_a.s"),  # already the new name
    ("CrawlerBody", "flange1"),  # a prefix renames only what lies under it
    ("PID", "u_s"), ("PID", "ry"),  # a whole name, not a prefix
    ("SmaWire", "T_amb"),  # a component that renamed nothing
])
def test_a_name_not_renamed_gives_none(component, name):
    assert renamed(component, name) is None


def test_every_new_name_is_a_port_of_its_component():
    """The table names catalogue components, and each new name (or prefix) is one of its
    variables today."""
    for component, table in RENAMED.items():
        assert component in CATALOGUE
        names = declarations(component)
        for new in table.values():
            assert any(n == new or new.endswith(".") and n.startswith(new) for n in names), \
                (component, new)

"""Parameter checks shared by the components' cores: one sentence naming the bad parameter."""
from __future__ import annotations

from collections.abc import Iterable


def require(params: object, positive: Iterable[str] = (),
            non_negative: Iterable[str] = ()) -> None:
    """Raise ValueError naming the first field of `params` in `positive` that is not > 0, then the
    first in `non_negative` that is not >= 0 (NaN fails both).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> require(SimpleNamespace(m=0.2, c=-1.0), positive=["m"], non_negative=["c"])
    Traceback (most recent call last):
    ValueError: c must be non-negative (got -1.0)
    """
    for name in positive:
        if not getattr(params, name) > 0:
            raise ValueError(f"{name} must be positive (got {getattr(params, name)!r})")
    for name in non_negative:
        if not getattr(params, name) >= 0:
            raise ValueError(f"{name} must be non-negative (got {getattr(params, name)!r})")

"""Output paths checked before the work, files replaced whole (never left half-written), and
long signals reduced for plotting (`envelope`)."""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

from musclesim.errors import UserError


def _can_write_in(folder: Path, path: Path, what: str) -> None:
    """Raise unless `folder` (for the output `path`, named as `what`) exists as a folder we can
    create files in, or can be made. A real probe, leaving nothing behind: a file created in it,
    or its first missing folder made, then removed; a refusal gives the reason the system gave
    and the path it gave it for."""
    top = folder
    while not top.parent.exists() and top.parent != top.parent.parent:
        top = top.parent
    base = top.parent if not top.exists() else top
    if not base.is_dir():
        raise UserError(f"{what} {path} cannot be written: {base} is a file, not a folder")
    try:
        if top.exists():
            fd, probe = tempfile.mkstemp(prefix=".musclesim-probe-", dir=top)
            os.close(fd)
            os.unlink(probe)
        else:
            os.mkdir(top)
            try:
                os.rmdir(top)
            except OSError:  # something else wrote into it meanwhile: it stays
                pass
    except FileExistsError:  # made meanwhile by another process: as good as made
        return
    except OSError as exc:
        made = f"a file in {top}" if top.exists() else str(exc.filename or top)
        raise UserError(f"{what} {path}: cannot create {made} "
                        f"({exc.strerror or type(exc).__name__})") from None


def check_output_dir(path: str | Path, what: str = "--out") -> None:
    """Refuse (UserError naming it as `what`), before any work, an output folder `path` that
    exists as a file or cannot be made or written into."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise UserError(f"{what} {path} is a file, not a folder")
    _can_write_in(path, path, what)


def check_output_file(path: str | Path, what: str = "--out") -> None:
    """Refuse (UserError naming it as `what`), before any work, an output file `path` that is a
    folder or whose folder cannot hold it."""
    path = Path(path)
    if path.is_dir():
        raise UserError(f"{what} {path} is a folder, not a file")
    _can_write_in(path.parent, path, what)


def replace_file(path: str | Path, data: str | bytes) -> None:
    """Write `data` (str or bytes) to `path` under a temporary name, then rename it in place, so
    that a reader sees the old file or the new one, never a part; a missing folder is made, as
    for the output folders (`check_output_file` checked that it can be)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    if isinstance(data, str):
        tmp.write_text(data, encoding="utf-8")
    else:
        tmp.write_bytes(data)
    os.replace(tmp, path)


def save_figure(fig: Any, path: str | Path, **options: Any) -> None:
    """Save the matplotlib figure `fig` at `path` the way `replace_file` writes a file (``savefig``
    `**options`)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.tmp{path.suffix}")  # the suffix names the format
    fig.savefig(tmp, **options)
    os.replace(tmp, path)


def envelope(t: np.ndarray, y: np.ndarray, bins: int) -> tuple[np.ndarray, np.ndarray]:
    """(`t`, `y`) reduced to the minimum and maximum of each of `bins` runs of samples (each at
    its run's first time), so that a plot of millions of samples keeps every peak (and draws in a
    fraction of the time: matplotlib's line and legend placement cost grows with the points)."""
    k = len(y) // bins
    if k < 2:
        return t, y
    n = len(y) // k * k
    runs = y[:n].reshape(-1, k)
    tt = np.repeat(t[:n:k], 2)
    yy = np.column_stack([runs.min(axis=1), runs.max(axis=1)]).ravel()
    return np.append(tt, t[n:]), np.append(yy, y[n:])


def check_archive(path: str | Path, suffix: str, what: str) -> Path:
    """`path` as a Path if it names a file ending in `suffix`; else UserError naming it as
    `what` (e.g. "the FMU")."""
    path = Path(path)
    if path.suffix != suffix:
        raise UserError(f"{what} {path} must have a name ending in {suffix}")
    if path.is_dir():
        raise UserError(f"{what} {path} names a folder, not a file")
    return path


def replace_zip(path: Path, fill: Callable[[zipfile.ZipFile], Any]) -> Path:
    """Write the zip archive `path` (its folder made if missing) by `fill(archive)`, an open
    ``zipfile.ZipFile``, under a temporary name renamed in place when `fill` returns: never a
    half-written archive, even when `fill` fails. Returns `path`."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp")
    try:
        with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as archive:
            fill(archive)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    os.replace(tmp, path)
    return path

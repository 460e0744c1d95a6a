"""The hysteresis data sets an SMA wire can use: the reference wire, or a shipped FORC data set.

Selected by an integer id (the SmaWire FMU's Real parameter ``hysteresis``):

- 0: the reference wire (`reference_wire.ReferenceWire`, the virtual hardware, parameters from
  ``params/flexinol-127um-90C.toml``) tabulated on a 1 C grid over its saturation range and at
  60..200 MPa every 10 MPa (`REFERENCE_STRESSES`): within 1.5e-4 strain (0.4 % of the maximum)
  of the wire's exact FORC increment everywhere inside;
- k >= 1: FORC data set k listed in ``data/forc-sets.toml`` (file format: `forcfile`).

Files are read below a root folder laid out like this package (an FMU passes its own resources,
since the folder a module was first imported from may be gone by the next instance). Tabulating
the reference wire takes ~0.5 s, so surfaces are built once per process per content and shared
(a `Hypersurface` is immutable; copies of a model share it).
"""
from __future__ import annotations

import hashlib
import tomllib
from pathlib import Path

from .surface import Hypersurface
from .reference_wire import DEFAULT_PARAMS, ReferenceWire, load_params

PACKAGE_DIR = Path(__file__).parent
INDEX = Path("data") / "forc-sets.toml"  # below the root
WIRE_PARAMS = Path("params") / DEFAULT_PARAMS.name  # below the root
REFERENCE_STEP = 1.0  # C, temperature grid of the tabulated reference wire (bilinear error ~1e-4)
# Pa: covers the study's 105-155 MPa (§forc-identification), a 100 g preload (77 MPa on 127 um,
# §sma-wire) and the data sheet's 172 MPa (§sma-material); 10 MPa steps add < 5e-5 strain to the
# temperature-grid error
REFERENCE_STRESSES = tuple(60e6 + 10e6 * k for k in range(15))

_SURFACES: dict[tuple[object, float], Hypersurface] = {}  # (what the surface is made from, single-surface stress or 0) -> Hypersurface


def shipped(resources: str | Path | None) -> Path:
    """The SMA data files' root an FMU ships below its `resources` folder (None: not in an FMU,
    this package's): the folder the modules were first imported from may be another FMU
    instance's, already deleted."""
    if resources is None:
        return PACKAGE_DIR
    return Path(resources) / "musclesim" / "components" / "sma"


def forc_sets(root: Path = PACKAGE_DIR) -> dict[int, tuple[Path, str]]:
    """{id: (path, description)} of the FORC data sets listed in data/forc-sets.toml below `root`.

    Raises
    ------
    ValueError
        Naming the index file and the bad entry.

    Examples
    --------
    >>> path, text = forc_sets()[1]
    >>> path.name
    'reference-wire-5C.csv'
    """
    index = Path(root) / INDEX
    try:
        sets = tomllib.loads(index.read_text(encoding="utf-8")).get("sets", {})
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"{index}: cannot read the FORC data set index ({exc})") from None
    found = {}
    for key, entry in sets.items():
        if not key.isdigit() or int(key) < 1 or not isinstance(entry, dict) \
                or not isinstance(entry.get("file"), str):
            raise ValueError(f"{index}: entry [sets.{key}] needs a positive integer id and a file")
        found[int(key)] = (index.parent / entry["file"], str(entry.get("description", "")))
    return found


def surface(k: float, sigma_surface: float = 0.0, root: Path = PACKAGE_DIR) -> Hypersurface:
    """The Hypersurface of data set `k` (0 = the reference wire) below `root`, or with
    `sigma_surface` > 0 its single constant-stress surface at that stress [Pa] (stress ignored,
    §position-control).

    Raises
    ------
    ValueError
        An unknown id, a ``sigma_surface`` outside the data set's stresses, or a bad data file;
        the message names the parameter (``hysteresis``, ``sigma_surface``) or the file.

    Examples
    --------
    >>> surface(1).stresses.tolist()
    [105000000.0, 115000000.0, 125000000.0, 135000000.0, 145000000.0]
    >>> surface(1, 120e6).stresses.tolist()
    [120000000.0]
    """
    source, build = _source(_id(k), Path(root))
    sigma_surface = float(sigma_surface)
    if (source, 0.0) not in _SURFACES:
        _SURFACES[source, 0.0] = build()
    full = _SURFACES[source, 0.0]
    if sigma_surface == 0:
        return full
    if not full.s_lo <= sigma_surface <= full.s_hi:
        raise ValueError(f"sigma_surface must be 0 (stress-aware hypersurface) or within the data "
                         f"set's stresses [{full.s_lo:g}, {full.s_hi:g}] Pa (got {sigma_surface:g})")
    if (source, sigma_surface) not in _SURFACES:
        _SURFACES[source, sigma_surface] = full.at_stress(sigma_surface)
    return _SURFACES[source, sigma_surface]


def _id(k):
    if not (float(k) == int(k) >= 0):
        raise ValueError(f"hysteresis must be 0 (reference wire) or the id of a FORC data set "
                         f"(got {k!r})")
    return int(k)


def _source(k, root):
    """(hashable identity of the data, function building the full surface) of data set k."""
    if k == 0:
        params = load_params(root / WIRE_PARAMS)
        return ("wire", params), lambda: _tabulate(ReferenceWire(params))
    sets = forc_sets(root)
    if k not in sets:
        raise ValueError(f"hysteresis = {k} is no data set: 0 is the reference wire, "
                         f"{root / INDEX} lists {sorted(sets)}")
    path = sets[k][0]
    try:
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the FORC data file ({exc})") from None
    return ("forc", digest), lambda: Hypersurface.load(path)


def _tabulate(wire):
    return wire.hypersurface(wire.grid(REFERENCE_STEP), REFERENCE_STRESSES)

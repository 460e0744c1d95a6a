"""Packaging a scenario for other tools: as an SSP 1.0 archive (its FMUs and SystemStructure.ssd,
for libcosim, ecos, FMPy's SSP simulator) or as one co-simulation FMU (FMPy's container FMU, for
tools that take one FMU).

The layer above a single run (``musclesim.cosim``: the scenario, the master's checks and its
exchange order, which the exports reuse) and beside the many-run layer (``musclesim.batch``), as
FMPy keeps its ``ssp/`` and ``container_fmu/`` apart from ``simulation.py``. `export_ssp` writes
the archive (`musclesim.export.ssp`), `export_fmu` the one FMU (`musclesim.export.container`);
both check the scenario against its FMUs first and refuse what the target cannot express, and
both name the system with `identifier` (letters, digits, underscores: what OMSimulator takes).
"""
from musclesim.export.container import export as export_fmu
from musclesim.export.ssp import export as export_ssp
from musclesim.export.ssp import identifier

__all__ = ["export_ssp", "export_fmu", "identifier"]

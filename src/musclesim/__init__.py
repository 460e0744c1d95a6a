"""musclesim: artificial-muscle physics as FMI co-simulation components (see README.md).

The framework is one subpackage per layer; each imports only the public interface (``__all__``)
of the layers below it, never a layer above:

    fmu         what ships inside every FMU: the pythonfmu Slave base class and the units
    components  (musclesim.components, from components/) the physics cores and thin FMU slaves
    cosim       one run: build, FMU hosting, scenario files, master, results
    batch       many runs: the Dask cluster, case folders, sweeps
    export      a scenario packaged for other tools: an SSP archive, one container FMU
    analysis    linear analysis and controller design, characterisation, the position tables
    hysteresis  FORC identification and validation, the loop explorer, Preisach timing
    diagnosis   measured data sets, the effect library, the sim-to-real gap diagnosis
    cli         the command line (imported by none)

`musclesim.errors` (the `UserError` every layer raises for a mistake a user can fix) sits below
them all.
"""

__version__ = "0.1.0"

"""musclesim: artificial-muscle physics as FMI co-simulation components (see README.md)."""

__version__ = "0.1.0"

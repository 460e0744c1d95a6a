"""Loads of the SMA wire on the position-control bench (SPEC.md 2.1, 2.4, 3.1)."""

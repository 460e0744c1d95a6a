"""Sensors with their imperfections as parameters, off by default (SPEC.md 2.1, 4)."""

"""The bending actuator of §bending-actuator: two antagonistic 50 um SMA wires beside an elastic
carbon-fibre beam pair, the beams' first bending mode, and its FMU.

- `beam`: the beam pair as a leaf spring (Euler-Bernoulli, pure end moment), deflection at a
  height, modal inertia, first resonance, the exact damped-oscillator step;
- `actuator`: the two wires (the SMA wire's thermal and Preisach cores, the 50 um parameter set)
  pulling eccentrically on the beams, stepped as one physics core;
- `slaves`: the BendingActuator FMU, a thin adapter over `actuator`.
"""

__all__ = ["actuator", "beam"]

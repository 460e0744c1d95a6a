"""The quadruped of §quadruped: four bending-actuator legs with anisotropic-friction feet on
a body moving along one axis, and the leg sequencer that pulses their wires.

- `body`: the body and its four feet (each foot the crawler's stick-slip friction of
  `crawler.friction` with direction-dependent coefficients), driven by the legs' deflections;
- `sequencer`: which leg's wire is pulsed when (gait phasing, frequency, pulse shape);
- `slaves`: the QuadrupedBody and LegSequencer FMUs, thin adapters over the two.

The legs are `bending.slaves.BendingActuator` FMUs, one per leg.
"""

__all__ = ["body", "sequencer"]

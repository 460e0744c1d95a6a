"""FMU slave of the capstan multiplier: a thin adapter over the compiled kernel of
musclesim.components.multiplier.capstan."""
from __future__ import annotations

import numpy as np

from musclesim.components.multiplier import capstan
from musclesim.components.sma import datasets, ports, thermal
from musclesim.fmu import KernelSlave, experiment

__all__ = ["CapstanMultiplier", "ZERO_C", "N"]

ZERO_C = capstan.ZERO_C  # K; the FMU speaks K, the cores C
N = capstan.MAX_SEGMENTS


class CapstanMultiplier(KernelSlave):
    """SMA wire folded over fixed capstans into segments, each with its own temperature, stress
    (capstan equation) and Preisach memory; one electrical element; end displacement = sum of the
    segments' contractions (§capstan-multiplier). Equations: §capstan-multiplier.

    Outputs depend on no input directly (like SmaWire), so loads and controllers close loops
    around it without an algebraic loop. Per-segment outputs beyond ``n_segments`` stay 0. The
    physics is `capstan.Multiplier`'s compiled kernel (`capstan.KERNEL`).
    """

    kernel = capstan.KERNEL

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Capstan multiplier: one SMA wire folded over fixed capstans into segments with "
                   "their own temperature, stress and hysteresis memory (§capstan-multiplier)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        # the fold's length and number of segments, the capstans' friction and the effects
        self.parameters_of(capstan.CapstanParams)
        for i in range(1, N + 1):
            self.parameter(f"segment_length[{i}]", 0.0, "m", f"Length of segment {i} (1 at the "
                           "clamp); 0 = an equal share of what the others leave of length (the "
                           "study leaves the spans open)", source="§capstan-multiplier")
        for j in range(1, N):
            self.parameter(f"wrap[{j}]", capstan.WRAP, "rad", f"Angle the wire sweeps on "
                           f"capstan {j}, between segments {j} and {j + 1} (about pi: the study's "
                           "tension ratio of 1.060-1.085 per contact; the exact wraps are open)",
                           source="§capstan-multiplier")
        # the straight wire's material and convection, declared with their calibrations once in
        # its core; the multiplier's length is the fold's and it has none of the wire's effects
        self.parameters_of(thermal.ThermalParams, skip=("length", "latent_heat", "h_exponent"),
                           overrides={"diameter": {"source": "§capstan-multiplier"}})
        self.parameter("T_init", 293.15, "K", "Initial temperature of every segment (assumption: "
                       "room temperature); the wire starts fully martensitic and heated to it",
                       source="§preisach")
        self.parameter("drive_current", 0.0, "1",
                       "Electrical input u: 0 = voltage [V] across the whole wire (default), "
                       "1 = current [A] through it (the kind of source is open in the study)",
                       source="§capstan-multiplier", type="Boolean")
        self.parameter("hysteresis", 0.0, "1", "Hysteresis data set: 0 = reference wire (1 C "
                       "grid, 60-200 MPa, which covers the clamp-side 135 MPa under 150 g); "
                       "k >= 1 = FORC data set k of sma/data/forc-sets.toml", source="§preisach",
                       type="Integer")
        ports.declare_ports(self, "Tensile load at the wire's load end, positive pulling (start: "
                            "a 150 g weight)", {
                                "flange.s": "End displacement: sum of the segments' contractions; "
                                            "positive = the load end moves toward the clamp",
                                "strain": "Mean strain flange.s / length",
                                "T": "Length-weighted mean temperature of the segments",
                                "stress": "Stress at the load end flange.f / cross-section over "
                                          "the last step",
                                "R": "Series resistance of the segments (§sma-material per-metre "
                                     "values)",
                                "P": "Joule heating power over the last step (input held, "
                                     "resistances at its start)"})
        for i in range(1, N + 1):
            self.output(f"segment[{i}].T", "K", f"Temperature of segment {i} (0 if unused)")
            self.output(f"segment[{i}].strain", "1", f"Strain of segment {i}, contraction / its "
                        "length (0 if unused)")
            self.output(f"segment[{i}].stress", "Pa", f"Stress of segment {i}, capstan-scaled "
                        "from the load end (0 if unused)")

    def setup(self) -> None:
        if self.drive_current not in (0.0, 1.0):
            raise ValueError(f"drive_current must be 0 (voltage) or 1 (current), "
                             f"got {self.drive_current!r}")
        if not self.T_init > 0:
            raise ValueError(f"T_init must be positive in K (got {self.T_init!r})")
        n = self.n_segments
        if not (n == int(n) and 1 <= n <= N):
            raise ValueError(f"n_segments must be an integer within 1..{N} (got {n!r})")
        n = int(n)
        # the straight wire's parameters as declared, but for its effects (the fold has none)
        wire = thermal.params_of(self, "current" if self.drive_current == 1 else "voltage",
                                 skip=("latent_heat", "h_exponent"))
        self.p = capstan.CapstanParams(
            length=self.length, n_segments=n,
            segment_lengths=tuple(getattr(self, f"segment_length[{i}]") for i in range(1, n + 1)),
            wraps=tuple(getattr(self, f"wrap[{j}]") for j in range(1, n)),
            mu_f=self.mu_f, composition_shift=self.composition_shift,
            contact_conductance=self.contact_conductance,
            source_resistance=self.source_resistance, stress_rise=self.stress_rise, wire=wire)
        self.p.check()
        self.surface = datasets.surface(self.hysteresis, 0.0, datasets.shipped(self.resources))
        self._start()

    def initialize(self) -> None:
        self._start()  # the inputs (ambient, load) are known now

    def _start(self) -> None:
        """A new fold (its one-time warnings too) started at T_init under the present inputs."""
        self.core = capstan.Multiplier(self.p, self.surface)
        self.kp, self.kx = self.core.kp, self.core.kx
        self.logged(self.core.start, self.T_init - ZERO_C, self.flange_f, self.time, self.u)

    def advance(self, t: float, dt: float) -> None:
        """The kernel's step over [`t`, `t` + `dt`] [s] with the inputs held, its inputs checked
        first and the stress clamps it met warned of after (the kernel keeps them in its
        state)."""
        ports.check_inputs(self.u, self.T_amb, self.flange_f, t)
        super().advance(t, dt)
        self.logged(self.core.warn_clamps)

    def restore_kernel(self, x: np.ndarray, u: np.ndarray, y: np.ndarray, time: float,
                       dirty: bool) -> None:
        """`KernelSlave.restore_kernel` (the state `x`, inputs `u`, outputs `y`, clock `time`
        [s] and `dirty` a master reached running the kernel itself), then the stress clamps the
        kernel kept in its state warned of as `advance` warns."""
        super().restore_kernel(x, u, y, time, dirty)
        self.logged(self.core.warn_clamps)

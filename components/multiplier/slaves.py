"""FMU slave of the capstan multiplier: a thin adapter over
musclesim.components.multiplier.capstan."""
import math

from musclesim.components.multiplier import capstan
from musclesim.components.sma import datasets, thermal
from musclesim.fmu import Slave, experiment

ZERO_C = 273.15  # K; the FMU speaks K, the cores C
LOAD_150G = 0.150 * 9.80665  # N, the 150 g weight of the multiplier tests (§capstan-multiplier)
N = capstan.MAX_SEGMENTS


class CapstanMultiplier(Slave):
    """SMA wire folded over fixed capstans into segments, each with its own temperature, stress
    (capstan equation) and Preisach memory; one electrical element; end displacement = sum of the
    segments' contractions (§capstan-multiplier). Equations: §capstan-multiplier.

    Outputs depend on no input directly (like SmaWire), so loads and controllers close loops
    around it without an algebraic loop. Per-segment outputs beyond ``n_segments`` stay 0.
    """

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Capstan multiplier: one SMA wire folded over fixed capstans into segments with "
                   "their own temperature, stress and hysteresis memory (§capstan-multiplier)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        t = thermal.ThermalParams()
        self.parameter("length", capstan.LENGTH, "m", "Total wire length (§capstan-multiplier: 214 "
                       "mm)")
        self.parameter("n_segments", 3.0, "1", f"Number of segments, 1..{N} "
                       "(§capstan-multiplier: three, one thermocouple each)")
        for i in range(1, N + 1):
            self.parameter(f"segment_length[{i}]", 0.0, "m", f"Length of segment {i} (1 at the "
                           "clamp); 0 = an equal share of what the others leave of length")
        for j in range(1, N):
            self.parameter(f"wrap[{j}]", capstan.WRAP, "rad", f"Angle the wire sweeps on "
                           f"capstan {j}, between segments {j} and {j + 1} "
                           "(§capstan-multiplier: about pi)")
        self.parameter("mu_f", capstan.MU_F, "1", "Friction coefficient of the wire on the "
                       "capstans (§capstan-multiplier: 0.0237, PTFE)")
        self.parameter("diameter", t.diameter, "m", "Wire diameter (§capstan-multiplier: 127 um)")
        self.parameter("density", t.density, "kg/m3", "Density of NiTi (§sma-material)")
        self.parameter("specific_heat", t.specific_heat, "J/(kg.K)", "Specific heat of NiTi "
                       "(§sma-material)")
        self.parameter("rho_martensite", t.rho_martensite, "Ohm.m",
                       "Resistivity of martensite, 80 uOhm cm (§sma-material)")
        self.parameter("rho_austenite", t.rho_austenite, "Ohm.m",
                       "Resistivity of austenite, 100 uOhm cm (§sma-material)")
        self.parameter("h", t.h, "W/(m2.K)", "Convection coefficient at 50 K excess (§convection)")
        self.parameter("T_init", 293.15, "K", "Initial temperature of every segment; the wire "
                       "starts fully martensitic and heated to it (§preisach memory)")
        self.parameter("drive_current", 0.0, "1",
                       "Electrical input u: 0 = voltage [V] across the whole wire (default), "
                       "1 = current [A] through it")
        self.parameter("hysteresis", 0.0, "1", "Hysteresis data set: 0 = reference wire (1 C "
                       "grid, 60-200 MPa); k >= 1 = FORC data set k of sma/data/forc-sets.toml")
        self.parameter("composition_shift", 0.0, "K", "Composition difference (effect, 0 = off): "
                       "the wire's hysteresis sees T - shift, transforming shift hotter")
        self.parameter("contact_conductance", 0.0, "W/K", "Capstan heat loss (effect, 0 = off): "
                       "heat conductance of each wire-on-PTFE contact to the room, shared by the "
                       "two segments it joins (§capstan-multiplier)")
        self.input("u", 0.0, "1", "Electrical input: voltage across the wire [V], or current "
                   "through it [A] when drive_current = 1")
        self.input("T_amb", 293.15, "K", "Ambient air temperature")
        self.input("flange.f", LOAD_150G, "N", "Tensile load at the wire's load end, positive "
                   "pulling (start: a 150 g weight, §capstan-multiplier)")
        self.output("flange.s", "m", "End displacement: sum of the segments' contractions; "
                    "positive = the load end moves toward the clamp")
        self.output("strain", "1", "Mean strain flange.s / length")
        self.output("T", "K", "Length-weighted mean temperature of the segments")
        self.output("stress", "Pa", "Stress at the load end flange.f / cross-section over the "
                    "last step")
        self.output("R", "Ohm", "Series resistance of the segments (§sma-material per-metre "
                    "values)")
        self.output("P", "W", "Joule heating power over the last step (input held, resistances "
                    "at its start)")
        for i in range(1, N + 1):
            self.output(f"segment[{i}].T", "K", f"Temperature of segment {i} (0 if unused)")
            self.output(f"segment[{i}].strain", "1", f"Strain of segment {i}, contraction / its "
                        "length (0 if unused)")
            self.output(f"segment[{i}].stress", "Pa", f"Stress of segment {i}, capstan-scaled "
                        "from the load end (0 if unused)")

    def setup(self):
        if self.drive_current not in (0.0, 1.0):
            raise ValueError(f"drive_current must be 0 (voltage) or 1 (current), "
                             f"got {self.drive_current!r}")
        if not self.T_init > 0:
            raise ValueError(f"T_init must be positive in K (got {self.T_init!r})")
        n = self.n_segments
        if not (n == int(n) and 1 <= n <= N):
            raise ValueError(f"n_segments must be an integer within 1..{N} (got {n!r})")
        n = int(n)
        wire = thermal.ThermalParams(
            length=self.length, diameter=self.diameter, density=self.density,
            specific_heat=self.specific_heat, rho_martensite=self.rho_martensite,
            rho_austenite=self.rho_austenite, h=self.h,
            drive="current" if self.drive_current == 1 else "voltage")
        self.p = capstan.CapstanParams(
            length=self.length, n_segments=n,
            segment_lengths=tuple(getattr(self, f"segment_length[{i}]") for i in range(1, n + 1)),
            wraps=tuple(getattr(self, f"wrap[{j}]") for j in range(1, n)),
            mu_f=self.mu_f, composition_shift=self.composition_shift,
            contact_conductance=self.contact_conductance, wire=wire)
        self.p.check()
        self.surface = datasets.surface(self.hysteresis, 0.0, datasets.shipped(self.resources))
        self._start()

    def initialize(self):
        self._start()  # the inputs (ambient, load) are known now

    def _start(self):
        self.core = capstan.Multiplier(self.p, self.surface)
        self.logged(self.core.start, self.T_init - ZERO_C, self.flange_f, self.time, self.u)
        self.stress_held = self.flange_f / self.core.area

    def evaluate(self):
        core = self.core
        s = core.displacement()
        self.flange_s = s
        self.strain = core.mean_strain()
        self.T = core.mean_temperature() + ZERO_C
        self.stress = self.stress_held
        self.R = core.resistance()
        self.P = core.power
        for i, seg in enumerate(core.segments, start=1):
            setattr(self, f"segment[{i}]_T", seg.T_C + ZERO_C)
            setattr(self, f"segment[{i}]_strain", seg.eps)
            setattr(self, f"segment[{i}]_stress", seg.sigma)

    def advance(self, t, dt):
        for name, value in (("u", self.u), ("T_amb", self.T_amb), ("flange.f", self.flange_f)):
            if not math.isfinite(value):
                raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
        self.logged(self.core.step, self.u, self.T_amb - ZERO_C, self.flange_f, t, dt)
        self.stress_held = self.flange_f / self.core.area

"""FMU slaves of the SMA wire and of its inverse: thin adapters over the thermal, Preisach, drift
and inverse cores."""
import math

from musclesim.components.sma import datasets, drift, ends, thermal
from musclesim.components.sma.inverse import InverseBases
from musclesim.components.sma.inverse import PreisachInverse as InverseCore
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.surface import clamp
from musclesim.fmu import Calibration, Slave, experiment

ZERO_C = 273.15  # K; the FMU speaks K, the cores C
LOAD_150G = 0.150 * 9.80665  # N, the 150 g weight of the multiplier tests (§capstan-multiplier):
#                              116 MPa
HYSTERESIS = ("Hysteresis data set: 0 = reference wire (1 C grid, 60-200 MPa); k >= 1 = FORC "
              "data set k of sma/data/forc-sets.toml shipped in the FMU")

_BASES = {}  # id(surface) -> (surface, its InverseBases); the surface is held, so ids stay unique


class SmaWire(Slave):
    """SMA wire: Joule heating and convection (§thermal-model) drive the modified Preisach model
    (§preisach).

    Per communication step, with the inputs held from its start: the temperature advances by the
    lumped thermal model (resistance from the martensite fraction at the start of the step), then
    the hysteresis model takes the new temperature and the stress flange.f / area; its strain gives
    the martensite fraction for the next step. No output depends directly on an input (stress and
    power are those of the step just taken), so the wire closes loops with controllers and loads
    without an algebraic loop. Temperatures outside the data set's grid (30..130 C) saturate the
    hysteresis (§thermal-model); stresses outside its stresses are clamped with one warning in the
    FMU log. Effects (latent heat, cold ends, h(T), drift, stress ignored and partly restored) are
    off by default. With cold ends (`end_cooling` > 0, `ends`) the temperature T is the core's, and
    each end zone has its own hysteresis memory at its own temperature; strain, resistance and power
    are the wire's, averaged over its length. Equations: §thermal-model and §preisach (docs/model/).
    """

    default_experiment = experiment(30.0, 0.0004)  # the SMA bench at 2.5 kHz, §sma-bench
    description = ("SMA wire: lumped thermal model with phase-dependent resistance and modified "
                   "Preisach hysteresis under stress (§thermal-model, §preisach)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        # geometry, material, convection and the thermal effects: declared in the thermal core
        self.parameters_of(thermal.ThermalParams)
        d = drift.DriftParams()
        self.parameter("T_init", 293.15, "K", "Initial wire temperature (assumption: room "
                       "temperature); the wire starts fully martensitic, as below 30 C, and "
                       "heated to it", source="§thermal-model, §preisach",
                       calibrate=Calibration(-5.0, 5.0, False, "the wire's temperature when the "
                                             "record starts"))
        self.parameter("drive_current", 0.0, "1", "Electrical input u: 0 = voltage [V] (default; "
                       "the study heated with 0-2.5 V), 1 = current [A] (the data sheets' "
                       "ratings, such as 0.3 A)", source="§thermal-model", type="Boolean")
        self.parameter("hysteresis", 0.0, "1", HYSTERESIS, source="§preisach", type="Integer")
        self.parameter("sigma_surface", 0.0, "Pa", "Stress ignored, 0 = off: > 0 uses the single "
                       "constant-stress surface at this stress (within the data set's stresses) "
                       "for every stress, as the study's comparison controller did",
                       source="§position-control")
        self.parameter("stress_blend", 0.0, "1", "Effect, 0 = off: with sigma_surface > 0, how "
                       "much the hysteresis follows the stress: it sees sigma_surface + "
                       "stress_blend (stress - sigma_surface) on the stress-aware data set",
                       source="§position-control, §named-effects", effect=(0.0, 1.0))
        self.parameter("end_cooling", 0.0, "1", "Effect, 0 = off: cold ends, the share of the "
                       "core's excess temperature lost at the clamps, G_c / (G_c + G_f) "
                       "(insulating clamps 0, metal clamps about 0.9)",
                       source="§named-effects, §thermal-model", effect=(0.0, 1.0))
        self.parameter("conductivity", 18.0, "W/(m.K)", "Thermal conductivity of NiTi "
                       "(literature); used only by the cold ends, whose fin length it sets",
                       source="§sma-material")
        self.parameter("drift_amplitude", d.amplitude_change, "1", "Effect, 0 = off: training/"
                       "fatigue drift, the settled relative change of the strain amplitude (the "
                       "study gives no magnitude)", source="§drift", effect=(-0.2, 0.2))
        self.parameter("drift_shift", d.shift, "K", "Effect, 0 = off: training/fatigue drift, "
                       "the settled shift of the transformation temperatures (the study gives no "
                       "magnitude)", source="§drift", effect=(-10.0, 10.0))
        self.parameter("drift_settle_cycles", d.cycles_to_settle, "1", "Training/fatigue drift: "
                       "e-folding number of cycles (95 % of the drift after the study's 13 tests "
                       "of 20 cycles, read as 13 tests in all)", source="§drift")
        self.parameter("drift_cycles_start", 0.0, "1", "Training/fatigue drift: transformation "
                       "cycles done before the run (a new wire 0, a later test of the study's "
                       "protocol 20 per earlier test)", source="§drift")
        self.parameter("hysteresis_shift", 0.0, "K", "Static shift of the transformation "
                       "temperatures: the hysteresis sees T - shift (composition, heat "
                       "treatment, a core hotter than the temperature measured)",
                       source="§preisach, §named-effects, §sma-material",
                       calibrate=Calibration(-8.0, 8.0, False, "transformation temperatures "
                                             "shift with composition and training"))
        self.parameter("strain_scale", 1.0, "1", "Factor on the transformation strain (the "
                       "wire's recoverable strain, its gauge length)",
                       source="§forc-identification, §sma-material",
                       calibrate=Calibration(0.85, 1.15, True, "the recoverable strain differs "
                                             "from wire to wire"))
        self.input("u", 0.0, "1", "Electrical input: voltage across the wire [V], or current "
                   "through it [A] when drive_current = 1")
        self.input("T_amb", 293.15, "K", "Ambient air temperature (assumption: a 20 C "
                   "laboratory)", source="§thermal-model", calibrate=thermal.AMBIENT)
        self.input("flange.f", LOAD_150G, "N", "Tensile load on the wire, positive pulling "
                   "(start: a 150 g weight)", source="§capstan-multiplier")
        self.output("T", "K", "Wire temperature")
        self.output("strain", "1", "Strain: contraction / length, positive = contraction "
                    "(§sma-wire)")
        self.output("flange.s", "m", "Contraction strain x length; positive = the wire shortens, "
                    "pulling its load toward the fixed clamp")
        self.output("stress", "Pa", "Tensile stress flange.f / cross-section over the last "
                    "step (§sma-wire)")
        self.output("R", "Ohm", "Electrical resistance R(xi) (§thermal-model)")
        self.output("P", "W", "Joule heating power over the last step (input held, resistance "
                    "at its start)")
        self.output("xi", "1", "Martensite fraction, 1 - hysteresis strain / its maximum")

    def setup(self):
        if self.drive_current not in (0.0, 1.0):
            raise ValueError(f"drive_current must be 0 (voltage) or 1 (current), "
                             f"got {self.drive_current!r}")
        if not self.T_init > 0:
            raise ValueError(f"T_init must be positive in K (got {self.T_init!r})")
        if not 0 <= self.stress_blend <= 1:
            raise ValueError(f"stress_blend must be within [0, 1] (got {self.stress_blend!r})")
        if not self.strain_scale > 0 or not math.isfinite(self.hysteresis_shift):
            raise ValueError(f"strain_scale must be positive and hysteresis_shift finite (got "
                             f"{self.strain_scale!r}, {self.hysteresis_shift!r})")
        if not self.drift_cycles_start >= 0:
            raise ValueError(f"drift_cycles_start must be non-negative "
                             f"(got {self.drift_cycles_start!r})")
        self.p = thermal.ThermalParams(
            length=self.length, diameter=self.diameter, density=self.density,
            specific_heat=self.specific_heat, rho_martensite=self.rho_martensite,
            rho_austenite=self.rho_austenite, h=self.h,
            drive="current" if self.drive_current == 1 else "voltage",
            latent_heat=self.latent_heat, h_exponent=self.h_exponent)
        self.p.check()
        self.dp = drift.DriftParams(amplitude_change=self.drift_amplitude, shift=self.drift_shift,
                                    cycles_to_settle=self.drift_settle_cycles)
        self.dp.check()
        root = datasets.shipped(self.resources)
        # stress_blend > 0 puts back part of the stress dependence that sigma_surface removed
        self.blend = self.sigma_surface > 0 and self.stress_blend > 0
        self.surface = datasets.surface(self.hysteresis, self.sigma_surface, root)
        if self.blend:
            self.surface = datasets.surface(self.hysteresis, 0.0, root)
        self.area = thermal.cross_section(self.p)
        self.zones = ends.zones(self.end_cooling, self.length, self.diameter, self.conductivity,
                                self.h)
        self._warned = set()
        self._eps_max_at = (None, None)  # (stress, F(a0, b0; stress)): the last one computed
        self._start()

    def initialize(self):
        self._start()  # the inputs (ambient, load) are known now

    def _start(self):
        """Initial state: a new (or drift_cycles_start old) wire heated to T_init."""
        self.T_C = self.T_init - ZERO_C
        self.cycles = self.drift_cycles_start
        self.model = PreisachModel(self.surface)
        self.zone_models = [PreisachModel(self.surface) for _ in self.zones]
        sigma = self._stress(self.time)
        self._strains(self.T_C, lambda m, T: m.reset(T, sigma, self.time), sigma)
        self.stress_held = self.flange_f / self.area
        self.P_held = thermal.joule_power(self.u, self.xi, self.p)

    def evaluate(self):
        self.T = self.T_C + ZERO_C
        self.strain = self.eps
        self.flange_s = self.eps * self.length
        self.stress = self.stress_held
        self.R = thermal.resistance(self.xi, self.p)
        self.P = self.P_held

    def advance(self, t, dt):
        for name, value in (("u", self.u), ("T_amb", self.T_amb), ("flange.f", self.flange_f)):
            if not math.isfinite(value):
                raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
        p, model = self.p, self.model
        sigma = self._stress(t)
        eps_max = self._eps_max(sigma)
        shift = drift.temperature_shift(self.cycles, self.dp)
        inputs = thermal.ThermalInputs(self._core_drive(), self.T_amb - ZERO_C, self.xi_core)
        if p.latent_heat == 0:  # the nominal path: no trial steps of the hysteresis model
            T_new = thermal.step(self.T_C, inputs, dt, p)
        else:
            def xi_at(T):
                return thermal.martensite_fraction(model.peek(self._seen(T, shift), sigma), eps_max)
            T_new = thermal.step_coupled(self.T_C, inputs, dt, p, xi_at)[0]
        xi_old = self.xi
        self.P_held = thermal.joule_power(self.u, xi_old, p)
        self._strains(T_new, lambda m, T: m.step(T, sigma, t + dt), sigma, shift)
        self.cycles = drift.count_cycles(self.cycles, xi_old, self.xi)
        self.stress_held = self.flange_f / self.area
        self.T_C = T_new

    def _strains(self, T_core, call, sigma, shift=0.0):
        """Step (or reset) the hysteresis memories with `call(model, seen temperature)`: the
        core's at `T_core`, each cold end zone's at its own temperature; set the strain and the
        martensite fractions of the core (its heating) and of the wire (its resistance)."""
        eps_max = self._eps_max(sigma)
        eps_core = eps = call(self.model, self._seen(T_core, shift))
        if self.zones:
            temps = ends.zone_temperatures(T_core, self.T_amb - ZERO_C, self.zones)
            eps = (1 - sum(w for w, _ in self.zones)) * eps_core + sum(
                w * call(m, self._seen(T, shift))
                for (w, _), m, T in zip(self.zones, self.zone_models, temps))
        self.xi_core = thermal.martensite_fraction(eps_core, eps_max)
        self.xi = thermal.martensite_fraction(eps, eps_max)
        self.eps = self.strain_scale * drift.strain_scale(self.cycles, self.dp) * eps

    def _core_drive(self):
        """The input that heats the core as the wire's current does: under voltage drive the
        current is set by the whole wire's resistance, the core heats at its own resistivity."""
        if not self.zones or self.p.drive == "current":
            return self.u
        return self.u * thermal.resistance(self.xi_core, self.p) / thermal.resistance(self.xi, self.p)

    def _seen(self, T, shift=0.0):
        """Temperature [C] the hysteresis sees: shifted (drift, calibration), saturated at the
        grid's ends."""
        return min(max(T - shift - self.hysteresis_shift, self.surface.t_lo), self.surface.t_hi)

    def _stress(self, t):
        """Stress [Pa] for the hysteresis: clamped to the data set's stresses, warned once."""
        sigma = self.flange_f / self.area
        if self.blend:
            sigma = self.sigma_surface + self.stress_blend * (sigma - self.sigma_surface)
        s = self.surface
        if len(s.stresses) > 1 and not s.s_lo <= sigma <= s.s_hi:
            sigma = self.logged(clamp, self._warned, "stress", sigma, s.s_lo, s.s_hi, "Pa", t)
        return sigma

    def _eps_max(self, sigma):
        """Maximum strain F(a0, b0; sigma) of the data set (one F evaluation per new stress)."""
        if self._eps_max_at[0] != sigma:
            s = self.surface
            self._eps_max_at = (sigma, s.F(s.t_hi, s.t_lo, sigma))
        return self._eps_max_at[1]


class PreisachInverse(Slave):
    """Inverse of the modified Preisach model (§preisach-inverse): reference strain and stress in,
    the temperature reference that makes the wire produce that strain out (feed-forward).

    A thin adapter over `inverse.PreisachInverse`. T_ref is direct feedthrough: at every
    communication point it is the core's `peek` at the present inputs (memory untouched); each
    step commits that sample with the core's `step`, so the memory sees every sample once, exactly
    as the core stepped by hand (clear at initialization, then one step per communication step =
    reset, step, step, ...). ``sigma_surface`` = 0: stress-aware inverse over the hypersurface;
    > 0: the single constant-stress surface at that stress for every stress ("stress ignored").
    Equations: §preisach-inverse.
    """

    default_experiment = experiment(550.0, 0.0004)  # sma-position-control, §position-control
    description = ("Feed-forward inverse of the modified Preisach model: reference strain and "
                   "stress in, temperature reference out (§position-control)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.parameter("hysteresis", 0.0, "1", HYSTERESIS + "; set it to the data set the "
                       "wire is modelled with", source="§preisach", type="Integer")
        self.parameter("sigma_surface", 0.0, "Pa",
                       "0 = stress-aware inverse over the hypersurface; > 0 = the single surface "
                       "at this stress for every stress, stress ignored, the study's comparison "
                       "inverse (within the data set's stresses: 105-145 MPa for data sets 1 and "
                       "2, 60-200 MPa for 0)", source="§position-control")
        self.input("eps_ref", 0.0, "1", "Reference strain: contraction / length, positive = "
                   "contraction, within [0, maximum strain of the data set] (start: a cold "
                   "wire)")
        self.input("sigma_ref", LOAD_150G / thermal.cross_section(thermal.ThermalParams()), "Pa",
                   "Reference stress (start: the 150 g weight on the 127 um wire, 116 MPa)")
        self.output("T_ref", "K", "Temperature reference for the wire's temperature controller",
                    depends=["eps_ref", "sigma_ref"])

    def setup(self):
        self.surface = datasets.surface(self.hysteresis, self.sigma_surface,
                                        datasets.shipped(self.resources))
        key = id(self.surface)
        if key not in _BASES:  # ~0.1-0.3 s per data set: once per process
            _BASES[key] = (self.surface, InverseBases(self.surface))
        self.bases = _BASES[key][1]
        self._start()

    def initialize(self):
        self._start()  # the inputs are known now

    def _start(self):
        self.core = InverseCore(self.surface, bases=self.bases)
        self._checked(self.time)
        self.logged(self.core.clear, self.sigma_ref, self.time)

    def evaluate(self):
        t = self.time
        self._checked(t)
        self.T_ref = self.logged(self.core.peek, self.eps_ref, self.sigma_ref, t) + ZERO_C

    def advance(self, t, dt):
        self._checked(t)
        self.logged(self.core.step, self.eps_ref, self.sigma_ref, t)

    def _checked(self, t):
        for name, value in (("eps_ref", self.eps_ref), ("sigma_ref", self.sigma_ref)):
            if not math.isfinite(value):
                raise ValueError(f"input {name} is {value!r} at t = {t:g} s")

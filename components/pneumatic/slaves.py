"""FMU slave of the soft pneumatic actuator: a thin adapter over components/pneumatic/actuator.py.

Equations, ports and sign conventions: §pneumatics (docs/model/pneumatics.md).
"""
from musclesim.components.pneumatic import actuator
from musclesim.fmu import Slave, experiment


class SoftActuator(Slave):
    """Silicone chamber fed through two PWM solenoid valves by an inflation and an exhaust pump
    (§crawler-hardware, §gait, §valves)."""

    default_experiment = experiment(30.0, 0.001)  # crawler-gait-forward, §gait
    display_units = {**Slave.display_units, "Pa": "kPa"}  # air pressures
    description = ("Soft pneumatic actuator: chamber (polytropic) filled and emptied through two "
                   "PWM solenoid valves (ISO 6358) from an inflation and an exhaust pump "
                   "(§crawler-hardware, §gait, §valves)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        d = actuator.ActuatorParams()
        self.parameter("central", d.central, "1", "1 = central longitudinal actuator (volume "
                       "from the elongation), 0 = extremal friction actuator (volume from the "
                       "contact) (§crawler-hardware)")
        self.parameter("s_a", d.s_a, "m2", "Cross-section: f_a = s_a p (§two-mass: 9.62e-4 m2)")
        self.parameter("V0", d.V0, "m3", "Chamber volume at rest (central: 30 mm inner diameter "
                       "x 83 mm, §crawler-hardware; extremal: 1.41e-5 m3, 30 mm x 20 mm)")
        self.parameter("dV_contact", d.dV_contact, "m3", "Extremal chamber's growth from casing "
                       "to silicone contact (assumption)")
        self.parameter("p_supply", d.p_supply, "Pa", "Gauge pressure of the inflation pump "
                       "(assumption: above the study's 20.7 kPa, §ideal-actuation)")
        self.parameter("p_exhaust", d.p_exhaust, "Pa", "Gauge pressure of the exhaust pump, "
                       "<= 0 (assumption)")
        self.parameter("C_in", d.C_in, "m3/(s.Pa)", "Sonic conductance of the inflation valve "
                       "(ISO 6358; assumption: a miniature solenoid valve)")
        self.parameter("C_out", d.C_out, "m3/(s.Pa)", "Sonic conductance of the exhaust valve "
                       "(ISO 6358; assumption: a miniature solenoid valve)")
        self.parameter("b", d.b, "1", "Critical pressure ratio of the valves (ISO 6358; "
                       "assumption)")
        self.parameter("T", d.T, "K", "Air temperature (the ISO 6358 reference, 293.15 K)")
        self.parameter("kappa", d.kappa, "1", "Polytropic exponent, 1 (isothermal) .. 1.4 "
                       "(adiabatic) (assumption: 1.2, §chamber)")
        self.parameter("f_pwm", d.f_pwm, "Hz", "PWM carrier frequency (assumption: the study "
                       "gives none)")
        self.parameter("pwm_phase", d.pwm_phase, "1", "Phase of a period at which the carrier's "
                       "periods start on the master's clock, periodic (1.25 is 0.25; "
                       "assumption: 0)")
        self.parameter("p_contact", d.p_contact, "Pa", "Gauge pressure above which the silicone "
                       "makes firm ground contact (assumption; §gait found it by eye)")
        self.parameter("t_contact", d.t_contact, "s", "Time of the contact's 0 -> 1 change; "
                       "<= 0: at once (assumption, §crawler-hardware: switching up to 0.4 s)")
        self.parameter("dt_sub", d.dt_sub, "s", "Internal step (10 per 1 ms communication step)")
        self.parameter("t_open_delay", d.t_open_delay, "s", "Effect, 0 = off: the valve opens "
                       "this long after its command rises (§valves: a few ms)")
        self.parameter("t_close_delay", d.t_close_delay, "s", "Effect, 0 = off: the valve closes "
                       "this long after its command falls (§valves: a few ms)")
        self.parameter("C_leak", d.C_leak, "m3/(s.Pa)", "Effect, 0 = off: sonic conductance of "
                       "a leak from the chamber to the atmosphere (§named-effects)")
        self.parameter("supply_drop", d.supply_drop, "1", "Effect, 0 = off: the supply pressure "
                       "sags to p_supply (1 - supply_drop) (§named-effects)")
        self.input("duty", 0.0, "1", "PWM duty, -1..1 (clamped, with one warning): > 0 drives the "
                   "inflation valve, < 0 the exhaust valve with duty -duty")
        self.input("flange_a.s", 0.0, "m", "Position of the rear block (central actuator; "
                   "variation from rest)")
        self.input("flange_b.s", 0.0, "m", "Position of the front block (central actuator; "
                   "variation from rest); elongation = flange_b.s - flange_a.s")
        self.output("p", "Pa", "Gauge pressure of the chamber")
        self.output("f_a", "N", "Actuator force s_a p pushing the blocks apart (§two-mass)")
        self.output("u", "1", "Contact of the extremal actuator with the ground, 0 (casing) .. 1 "
                    "(silicone): the friction indicator")
        self.output("m_flow", "kg/s", "Net mass flow into the chamber, averaged over the last "
                    "step")

    def setup(self):
        self.params = self.core_params(actuator.ActuatorParams)
        self.core = actuator.Actuator(self.params, self._elongation())
        self.m_flow = 0.0

    def initialize(self):
        self.core = actuator.Actuator(self.params, self._elongation())
        self.m_flow = 0.0

    def evaluate(self):
        self.p = self.core.pressure
        self.f_a = self.params.s_a * self.core.pressure
        self.u = self.core.contact

    def advance(self, t, dt):
        duty = self.clamped_input("duty", -1.0, 1.0, t)
        mass = self.core.step(t, dt, duty, self._elongation())
        self.m_flow = mass / dt if dt > 0 else 0.0

    def _elongation(self):
        return self.flange_b_s - self.flange_a_s

"""FMU slaves of the controllers: thin adapters over musclesim.components.control.pid and .relay."""
from __future__ import annotations

import math

from musclesim.components.control import pid, relay
from musclesim.components.control.pid import SCHEDULE_K
from musclesim.fmu import Slave, experiment

UNLIMITED = 1e30  # output limits that never act (FMI start values must be finite)


class _PIDBase(Slave):
    """Inputs u_s (reference), u_m (measurement); output y = PID(u_s - u_m) with direct
    feedthrough; limits and filter as parameters. The ports are named as in the Modelica Standard
    Library's LimPID (scenario format 2; earlier r, y, u: `musclesim.components.RENAMED`)."""

    def _declare_common(self):
        # the core's limits are infinite by default; an FMU's start values must be finite
        self.parameter("u_min", -UNLIMITED, "1", "Lower output limit (-1e30: none)")
        self.parameter("u_max", UNLIMITED, "1", "Upper output limit (1e30: none)")
        self.input("u_s", 0.0, "1", "Reference (set point)")
        self.input("u_m", 0.0, "1", "Measurement")
        self.output("y", "1", "Controller output", depends=["u_s", "u_m"])
        self.output("e", "1", "Control error u_s - u_m", depends=["u_s", "u_m"])

    def setup(self) -> None:
        Kp, Ki, Kd = self.gains()
        self.p = pid.PIDParams(Kp, Ki, Kd, self.Tf, self.u_min, self.u_max)
        self.p.check()
        self.state = pid.PIDState()
        self.dt = 0.0

    def evaluate(self) -> None:
        self.e = self.u_s - self.u_m
        self.y = pid.output(self.state, self.u_s, self.u_m, self.dt, self.gains(), self.p)

    def advance(self, t: float, dt: float) -> None:
        """Advance the state over [`t`, `t` + `dt`] [s] with the inputs held."""
        self.dt = dt
        self.state = pid.update(self.state, self.u_s, self.u_m, dt, self.gains(), self.p)


class PID(_PIDBase):
    """Discrete PID controller with derivative filter, output limits and anti-windup."""

    description = "Discrete PID: derivative on measurement, output limits, conditional integration"

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(pid.PIDParams)
        self._declare_common()

    def gains(self) -> tuple[float, ...]:
        """Current (Kp, Ki, Kd)."""
        return self.Kp, self.Ki, self.Kd


class GainScheduledPID(_PIDBase):
    """PID whose gains are interpolated from 21 sets scheduled on the reference
    (§temperature-control)."""

    default_experiment = experiment(30.0, 0.0004)  # sma-temperature-tracking, §temperature-control
    description = ("Gain-scheduled PID: 21 gain sets on the reference, 30..130 C every 5 C, "
                   "linear in between (§temperature-control)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        # the scheduled gains are tables, not the core's single gains
        for i, x in enumerate(SCHEDULE_K, start=1):
            self.parameter(f"x[{i}]", x, "1", f"Scheduling point {i} of the reference",
                           source="§temperature-control")
        for name, what in (("Kp", "Proportional gain"), ("Ki", "Integral gain [1/s]"),
                           ("Kd", "Derivative gain [s]")):
            for i in range(1, 22):
                self.parameter(f"{name}[{i}]", 1.0 if name == "Kp" else 0.0, "1",
                               f"{what} at scheduling point {i}")
        self.parameters_of(pid.PIDParams, skip=("Kp", "Ki", "Kd"))
        self._declare_common()

    def setup(self) -> None:
        attr = lambda name, i: getattr(self, f"{name}[{i}]")
        self.breakpoints = [attr("x", i) for i in range(1, 22)]
        if any(b >= c for b, c in zip(self.breakpoints, self.breakpoints[1:])):
            raise ValueError("the scheduling points x[1..21] must increase strictly")
        self.table = [(attr("Kp", i), attr("Ki", i), attr("Kd", i)) for i in range(1, 22)]
        super().setup()

    def gains(self) -> tuple[float, ...]:
        """(Kp, Ki, Kd) interpolated at the current reference."""
        return pid.scheduled_gains(self.u_s, self.breakpoints, self.table)


class BangBang(Slave):
    """Relay temperature controller with hysteresis: on when the measured temperature falls to
    T_on, off when it rises to T_off (§multiplier-experiments: 75 C and 90 C); output y: u_on or
    u_off (named u before format 2).
    A thin adapter over `relay`; equations: §bang-bang.
    """

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Bang-bang (relay) temperature controller: on when T falls to T_on, off when T "
                   "rises to T_off; output u_on / u_off (§multiplier-experiments)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        d = relay.RelayParams()
        # the core's thresholds y_on, y_off, named here for the temperature they compare
        self.parameter("T_on", d.y_on, "K", "Switch on when the temperature falls to this (the "
                       "study's 75 C)", source="§multiplier-experiments")
        self.parameter("T_off", d.y_off, "K", "Switch off when the temperature rises to this (the "
                       "study's 90 C)", source="§multiplier-experiments")
        self.parameters_of(relay.RelayParams)
        self.input("T", 293.15, "K", "Measured temperature (e.g. a thermocouple's T_meas)")
        self.output("y", "1", "Controller output u_on or u_off", depends=["T"])
        self.output("on", "1", "Relay state: 1 on, 0 off", depends=["T"], type="Boolean")

    def setup(self) -> None:
        self.p = relay.RelayParams(y_on=self.T_on, y_off=self.T_off, u_on=self.u_on,
                                   u_off=self.u_off, initially_on=self.initially_on)
        self.p.check()
        self.state = relay.initial_state(self.T, self.p)

    def initialize(self) -> None:
        self.state = relay.initial_state(self.T, self.p)  # the measurement is known now

    def _checked(self, t):
        if math.isnan(self.T):
            raise ValueError(f"input T is NaN at t = {t:g} s")

    def evaluate(self) -> None:
        self._checked(self.time)
        on = relay.switch(self.state, self.T, self.p)
        self.y = relay.output(on, self.p)
        self.on = 1.0 if on else 0.0

    def advance(self, t: float, dt: float) -> None:
        """Advance the state over [`t`, `t` + `dt`] [s] with the inputs held."""
        self._checked(t)
        self.state = relay.switch(self.state, self.T, self.p)

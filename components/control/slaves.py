"""FMU slaves of the controllers: kernels (`musclesim.fmu.kernel`) over the jit cores of
musclesim.components.control.pid and .relay.

Packed layouts (``kp``, ``kx``; index constants below):

- PID: kp = [Tf, u_min, u_max, Kp, Ki, Kd]; GainScheduledPID: kp = [Tf, u_min, u_max, n, the n
  breakpoints, the n Kp, the n Ki, the n Kd] (`pid.pack_schedule`); both kx = [integral, last
  derivative term, last measurement (NaN: none yet), last step].
- BangBang: kp = [y_on (T_on), y_off (T_off), u_on, u_off, initially_on], kx = [on (1 or 0)].
"""
from __future__ import annotations

import math

import numpy as np

from musclesim.components.control import pid, relay
from musclesim.components.control.pid import SCHEDULE_K
from musclesim.fmu import Kernel, KernelSlave, experiment, jit

UNLIMITED = 1e30  # output limits that never act (FMI start values must be finite)

TF, U_MIN, U_MAX, KP, KI, KD = range(6)  # PID's kp; GainScheduledPID's: TF, U_MIN, U_MAX, N, ...
N = 3  # GainScheduledPID: number of breakpoints, the schedule (pid.gains_at) from N + 1
INTEGRAL, DERIVATIVE, Y_LAST, DT_LAST = range(4)  # kx of both PIDs
Y_ON, Y_OFF, U_ON, U_OFF, INITIALLY_ON = range(5)  # BangBang's kp; its kx = [on]


@jit
def pid_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """PID's kernel: writes the outputs `y` = (y, e) from the state `x` and the inputs `u` =
    (u_s, u_m) of the parameters `p` at time `t`."""
    y[0] = pid.output_core(x[INTEGRAL], x[DERIVATIVE], x[Y_LAST], u[0], u[1], x[DT_LAST], p[KP],
                           p[KD], p[TF], p[U_MIN], p[U_MAX])
    y[1] = u[0] - u[1]


@jit
def pid_advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
                dt: float) -> None:
    """PID's kernel: one sample's step of `dt` [s] from `t` of the state `x` in place, with the
    inputs `u`, outputs `y` and parameters `p`."""
    x[INTEGRAL], x[DERIVATIVE], x[Y_LAST] = pid.update_core(
        x[INTEGRAL], x[DERIVATIVE], x[Y_LAST], u[0], u[1], dt, p[KP], p[KI], p[KD], p[TF],
        p[U_MIN], p[U_MAX])
    x[DT_LAST] = dt


@jit
def scheduled_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float,
                       y: np.ndarray) -> None:
    """GainScheduledPID's kernel: writes the outputs `y` = (y, e) from the state `x` and the
    inputs `u` = (u_s, u_m) of the parameters `p` at time `t`, the gains at the reference."""
    Kp, _, Kd = pid.gains_at(u[0], p, N + 1, int(p[N]))
    y[0] = pid.output_core(x[INTEGRAL], x[DERIVATIVE], x[Y_LAST], u[0], u[1], x[DT_LAST], Kp, Kd,
                           p[TF], p[U_MIN], p[U_MAX])
    y[1] = u[0] - u[1]


@jit
def scheduled_advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
                      dt: float) -> None:
    """GainScheduledPID's kernel: one sample's step of `dt` [s] from `t` of the state `x` in
    place, with the inputs `u`, outputs `y` and parameters `p`, the gains at the reference."""
    Kp, Ki, Kd = pid.gains_at(u[0], p, N + 1, int(p[N]))
    x[INTEGRAL], x[DERIVATIVE], x[Y_LAST] = pid.update_core(
        x[INTEGRAL], x[DERIVATIVE], x[Y_LAST], u[0], u[1], dt, Kp, Ki, Kd, p[TF], p[U_MIN],
        p[U_MAX])
    x[DT_LAST] = dt


@jit
def relay_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """BangBang's kernel: writes the outputs `y` = (y, on) after seeing the input `u` = (T) in
    the state `x`, of the parameters `p` at time `t`."""
    on = relay.switch_core(x[0] == 1.0, u[0], p[Y_ON], p[Y_OFF])
    y[0] = relay.output_core(on, p[U_ON], p[U_OFF])
    y[1] = 1.0 if on else 0.0


@jit
def relay_advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
                  dt: float) -> None:
    """BangBang's kernel: the relay's state `x` (in place) after seeing the input `u` = (T), of
    the parameters `p`; the outputs `y`, time `t` and step `dt` are not used."""
    x[0] = 1.0 if relay.switch_core(x[0] == 1.0, u[0], p[Y_ON], p[Y_OFF]) else 0.0


class _PIDBase(KernelSlave):
    """Inputs u_s (reference), u_m (measurement); output y = PID(u_s - u_m) with direct
    feedthrough; limits and filter as parameters. The ports are named as in the Modelica Standard
    Library's LimPID (scenario format 2; earlier r, y, u: `musclesim.components.RENAMED`)."""

    def _declare_common(self):
        # the core's limits are infinite by default; an FMU's start values must be finite
        self.parameter("u_min", -UNLIMITED, "1", "Lower output limit (-1e30: none)")
        self.parameter("u_max", UNLIMITED, "1", "Upper output limit (1e30: none)")
        # the reference in the measurement's unit, which the scenario's wiring gives
        self.input("u_s", 0.0, "1", "Reference (set point)", same_unit_as="u_m")
        self.input("u_m", 0.0, "1", "Measurement")
        self.output("y", "1", "Controller output", depends=["u_s", "u_m"])
        # the error is of the measurement's quantity; the output y is not (a voltage, a duty)
        self.output("e", "1", "Control error u_s - u_m", depends=["u_s", "u_m"],
                    same_unit_as="u_m")

    def setup(self) -> None:
        Kp, Ki, Kd = self.gains()
        self.p = pid.PIDParams(Kp, Ki, Kd, self.Tf, self.u_min, self.u_max)
        self.p.check()
        self.kx = np.array([0.0, 0.0, math.nan, 0.0])  # no sample yet (pid.PIDState), no step


class PID(_PIDBase):
    """Discrete PID controller with derivative filter, output limits and anti-windup."""

    description = "Discrete PID: derivative on measurement, output limits, conditional integration"
    kernel = Kernel(pid_evaluate, pid_advance, ("u_s", "u_m"), ("y", "e"))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(pid.PIDParams)
        self._declare_common()

    def setup(self) -> None:
        super().setup()
        self.kp = np.array([self.Tf, self.u_min, self.u_max, self.Kp, self.Ki, self.Kd])

    def gains(self) -> tuple[float, ...]:
        """Current (Kp, Ki, Kd)."""
        return self.Kp, self.Ki, self.Kd


class GainScheduledPID(_PIDBase):
    """PID whose gains are interpolated from 21 sets scheduled on the reference
    (§temperature-control)."""

    default_experiment = experiment(30.0, 0.0004)  # sma-temperature-tracking, §temperature-control
    description = ("Gain-scheduled PID: 21 gain sets on the reference, 30..130 C every 5 C, "
                   "linear in between (§temperature-control)")
    # a NaN reference has no gains: refused (a range without bounds: no clamp, no warning)
    kernel = Kernel(scheduled_evaluate, scheduled_advance, ("u_s", "u_m"), ("y", "e"),
                    clamps=(("u_s", -math.inf, math.inf),))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        # the scheduled gains are tables, not the core's single gains
        for i, x in enumerate(SCHEDULE_K, start=1):
            self.parameter(f"x[{i}]", x, "1", f"Scheduling point {i} of the reference",
                           source="§temperature-control", same_unit_as="u_s")
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
        self.kp = np.concatenate(([self.Tf, self.u_min, self.u_max, len(self.breakpoints)],
                                  pid.pack_schedule(self.breakpoints, self.table)))

    def gains(self) -> tuple[float, ...]:
        """(Kp, Ki, Kd) interpolated at the current reference."""
        return pid.scheduled_gains(self.u_s, self.breakpoints, self.table)


class BangBang(KernelSlave):
    """Relay temperature controller with hysteresis: on when the measured temperature falls to
    T_on, off when it rises to T_off (§multiplier-experiments: 75 C and 90 C); output y: u_on or
    u_off (named u before format 2).
    A thin adapter over `relay`; equations: §bang-bang.
    """

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Bang-bang (relay) temperature controller: on when T falls to T_on, off when T "
                   "rises to T_off; output u_on / u_off (§multiplier-experiments)")
    # a NaN temperature is refused ("input T is NaN at t = ..."): a range without bounds
    kernel = Kernel(relay_evaluate, relay_advance, ("T",), ("y", "on"),
                    clamps=(("T", -math.inf, math.inf),))

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
        self.kp = np.array([self.T_on, self.T_off, self.u_on, self.u_off, self.initially_on])
        self.initialize()

    def initialize(self) -> None:
        # the measurement is known now
        self.kx = np.array([1.0 if relay.initial_state(self.T, self.p) else 0.0])

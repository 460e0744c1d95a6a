"""FMU slaves of the sensors: thin adapters over musclesim.components.sensors.sensor."""
from __future__ import annotations

from typing import Any

from musclesim.components.sensors import sensor
from musclesim.fmu import Calibration, Kernel, KernelSlave, Slave, experiment

# the diagnosis's calibration of a load cell's, laser's or pressure sensor's gain
AMPLIFIER_GAIN = Calibration(0.95, 1.05, True, "the sensor's and its amplifier's "
                             "calibration")


class _ScalarSensor(KernelSlave):
    """A sensor reading one signal with lag, gain, bias, noise and quantisation, all off by
    default.

    Subclasses name the measured input and the reading (`signal`, `measured`, `unit`), the input's
    start value, what lags (`element`), the signal value its gain leaves as it is (`origin`) and
    the diagnosis roles of their parameters (`roles`: name -> `declare`'s source, effect or
    calibrate).
    """

    signal = measured = unit = element = signal_description = ""
    start = origin = 0.0
    signal_plausible: str | None = None  # `declare`'s plausible of the input: its unit's range
    roles: dict[str, dict[str, object]] = {}

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        u = self.unit
        own = {"tau": {"description": f"Time constant of the first-order lag of the "
                                      f"{self.element} (0 = none)"},
               "gain": {"description": f"Reading gain about {self.origin:g} {u} (1 = exact)"},
               **{name: {"unit": u} for name in ("bias", "noise_std", "quantum")}}
        self.parameters_of(sensor.SensorParams, overrides={
            name: {**own.get(name, {}), **self.roles.get(name, {})} for name in own | self.roles})
        self.input(self.signal, self.start, u, self.signal_description,
                   plausible=self.signal_plausible)
        self.output(self.measured, u, f"Measured {self.signal_description[0].lower()}"
                    f"{self.signal_description[1:]}", depends=[self.signal])

    def setup(self) -> None:
        # not self.p: PressureSensor reads "p"; `origin` is the class's
        self.params = self.core_params(sensor.SensorParams)
        self.kp = sensor.pack(self.params)
        self.kx = sensor.start_state(self.params)  # the generator and the first noise sample
        self._settle()

    def initialize(self) -> None:
        self._settle()

    def _settle(self) -> None:
        """The sensing element settled on the signal's present value (without a lag, the
        reading is the signal itself)."""
        u = getattr(self, self.signal)
        self.kx[sensor.HELD], self.kx[sensor.WEIGHT] = (0.0, 1.0) if self.params.tau <= 0 else \
            (u, 0.0)


def _kernel(signal: str, measured: str) -> Kernel:
    """The kernel of a sensor reading the input `signal` into the output `measured`."""
    return Kernel(sensor.evaluate, sensor.advance, (signal,), (measured,))


class Thermocouple(_ScalarSensor):
    """Temperature sensor with lag, bias, noise and quantisation, all off by default
    (§sma-bench)."""

    default_experiment = experiment(30.0, 0.0004)  # the SMA bench at 2.5 kHz, §sma-bench
    description = ("Thermocouple: first-order lag, bias, seeded noise, quantisation (§sma-bench, "
                   "§named-effects)")
    signal, measured, unit, start = "T", "T_meas", "K", 293.15
    kernel = _kernel(signal, measured)
    origin = 273.15  # K: a thermocouple's gain error is a share of the reading in C
    element, signal_description = "junction", "Temperature of the wire"
    # its offset is the effect "thermocouple bias", so its gain alone is calibrated
    roles = {"tau": {"source": "§sma-wire, §named-effects", "effect": (0.0, 2.0)},
             "bias": {"source": "§named-effects, §sensors", "effect": (-10.0, 10.0)},
             "gain": {"source": "§sma-bench", "calibrate": Calibration(
                 0.9925, 1.0075, True, "a standard thermocouple's tolerance: 0.75 % of the "
                 "reading in C (IEC 60584 class 2)")}}


class LoadCell(_ScalarSensor):
    """Load cell on the wire's load with lag, bias, noise and quantisation, all off (§sma-bench)."""

    default_experiment = experiment(30.0, 0.0004)  # the SMA bench at 2.5 kHz, §sma-bench
    description = ("Load cell: tension on the wire with first-order lag, bias, seeded noise, "
                   "quantisation (§sma-bench, §named-effects)")
    signal, measured, unit = "f", "f_meas", "N"
    kernel = _kernel(signal, measured)
    element, signal_description = "load cell and its amplifier", "Tension on the wire"
    roles = {"tau": {"source": "§sma-bench, §named-effects", "effect": (0.0, 0.5)},
             "gain": {"source": "§sma-bench", "calibrate": AMPLIFIER_GAIN}}


class LaserSensor(_ScalarSensor):
    """Laser displacement sensor on the wire's contraction, imperfections off (§sma-bench)."""

    default_experiment = experiment(30.0, 0.0004)  # the SMA bench at 2.5 kHz, §sma-bench
    description = ("Laser displacement sensor: wire contraction with first-order lag, bias, "
                   "seeded noise, quantisation (§sma-bench, §named-effects)")
    signal, measured, unit = "s", "s_meas", "m"
    signal_plausible = "difference"  # a contraction, negative where the wire lengthens
    kernel = _kernel(signal, measured)
    element, signal_description = "sensor's filter", "Contraction of the wire (SmaWire flange.s)"
    roles = {"noise_std": {"source": "§sma-bench, §named-effects", "effect": (0.0, 2e-5)},
             "gain": {"source": "§sma-bench", "calibrate": AMPLIFIER_GAIN}}


class PressureSensor(_ScalarSensor):
    """Pressure sensor on a soft actuator's chamber, imperfections off by default
    (§crawler-hardware)."""

    default_experiment = experiment(30.0, 0.001)  # crawler-gait-forward, §gait
    display_units = {**Slave.display_units, "Pa": "kPa"}  # air pressures
    description = ("Pressure sensor: chamber gauge pressure with first-order lag, bias, seeded "
                   "noise, quantisation (§crawler-hardware, §named-effects)")
    signal, measured, unit = "p", "p_meas", "Pa"
    signal_plausible = "gauge pressure"
    kernel = _kernel(signal, measured)
    element, signal_description = "pressure sensor", "Gauge pressure of the chamber"
    roles = {"gain": {"source": "§crawler-hardware", "calibrate": AMPLIFIER_GAIN}}

"""FMU slaves of the sensors: thin adapters over musclesim.components.sensors.thermocouple."""
from musclesim.components.sensors import thermocouple as tc
from musclesim.fmislave import Slave


class Thermocouple(Slave):
    """Temperature sensor with lag, bias, noise and quantisation, all off by default (SPEC 2.1)."""

    description = "Thermocouple: first-order lag, bias, seeded noise, quantisation (SPEC 2.1, 4)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.parameter("tau", 0.0, "s", "Lag time constant of the junction (effect off: 0)")
        self.parameter("bias", 0.0, "K", "Reading bias (effect off: 0)")
        self.parameter("noise_std", 0.0, "K", "Standard deviation of the reading noise (off: 0)")
        self.parameter("quantum", 0.0, "K", "Quantisation step of the reading (off: 0)")
        self.parameter("seed", 0.0, "1", "Seed of the noise generator")
        self.input("T", 293.15, "K", "Temperature of the wire")
        self.output("T_meas", "K", "Measured temperature", depends=["T"])

    def setup(self):
        self.p = self.core_params(tc.SensorParams)
        self.rng = tc.make_rng(self.p)
        self.x = self.T
        self.noise = tc.noise_sample(self.p, self.rng)

    def initialize(self):
        self.x = self.T  # the junction starts at the wire's temperature

    def evaluate(self):
        self.T_meas = tc.reading(self.T if self.p.tau <= 0 else self.x, self.p, self.noise)

    def advance(self, t, dt):
        self.x = tc.lag(self.x, self.T, dt, self.p.tau)
        self.noise = tc.noise_sample(self.p, self.rng)  # one sample per communication step

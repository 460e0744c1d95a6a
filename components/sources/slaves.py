"""FMU slaves of the sources: thin adapters over musclesim.components.sources.signals and .forc."""
from musclesim.components.sources import forc, signals
from musclesim.fmislave import Slave


class SignalSource(Slave):
    """Constant, sine, square or triangle signal (references, loads)."""

    description = "Signal source: constant, sine, square or triangle wave around an offset"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.parameter("kind", 0.0, "1", "Wave: 0 constant, 1 sine, 2 square, 3 triangle")
        self.parameter("offset", 0.0, "1", "Offset (the value before t_start)")
        self.parameter("amplitude", 0.0, "1", "Amplitude")
        self.parameter("frequency", 0.0, "Hz", "Frequency")
        self.parameter("phase", 0.0, "rad", "Phase")
        self.parameter("t_start", 0.0, "s", "Start of the wave")
        self.output("y", "1", "Signal")

    def setup(self):
        self.p = self.core_params(signals.SignalParams)

    def evaluate(self):
        self.y = signals.value(self.time, self.p)


class ForcReference(Slave):
    """Temperature reference of the FORC identification runs with run index and phase markers."""

    description = ("FORC experiment reference (SPEC 2.3): run j heats from T_low to T_low + j "
                   "T_step along a raised cosine and cools back; outputs run index and phase")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        d = forc.ForcParams()
        self.parameter("T_low", d.T_low, "K", "Lower grid temperature b0, start and end of every "
                       "run (SPEC 2.3: 30 C)")
        self.parameter("T_high", d.T_high, "K", "Peak of the last run a0 (SPEC 2.3: 130 C)")
        self.parameter("T_step", d.T_step, "K", "Grid step between the runs' peaks (SPEC 2.2: 5 K)")
        self.parameter("period", d.period, "s", "Duration of one run (heating half + cooling "
                       "half); must not outrun free cooling")
        self.parameter("t_start", d.t_start, "s", "Start of the first run (T_low held before)")
        self.output("T_ref", "K", "Reference temperature")
        self.output("run", "1", "Run index j = 0..n-1 (peak T_low + j T_step); -1 outside the runs")
        self.output("phase", "1", "+1 heating half, -1 cooling half, 0 outside the runs")

    def setup(self):
        self.p = self.core_params(forc.ForcParams)

    def evaluate(self):
        self.T_ref, self.run, self.phase = forc.value(self.time, self.p)

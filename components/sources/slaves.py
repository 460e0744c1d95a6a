"""FMU slave of the signal source: a thin adapter over musclesim.components.sources.signals."""
from musclesim.components.sources import signals
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
        self.p = signals.SignalParams(**{n: getattr(self, n)
                                         for n in signals.SignalParams.__dataclass_fields__})
        self.p.check()

    def evaluate(self):
        self.y = signals.value(self.time, self.p)

"""The leg sequencer (components/quadruped/sequencer.py, §quadruped): each wire pulsed at its
phase."""
import pytest

from musclesim.components.quadruped import sequencer


def test_sequencer_pulses_each_wire_at_its_phase():
    p = sequencer.SequencerParams()
    t = [k * 1e-4 for k in range(2500)]  # one 0.25 s period
    on = [[sum(sequencer.voltages(tk, p)[leg][w] > 0 for tk in t) * 1e-4 for w in (0, 1)]
          for leg in range(4)]
    for leg in range(4):
        assert on[leg] == [pytest.approx(0.0125, abs=2e-4)] * 2  # 12.5 ms per wire (§quadruped)
    first = [[next(tk for tk in t if sequencer.voltages(tk, p)[leg][w] > 0 or tk == t[-1])
              for w in (0, 1)] for leg in range(4)]
    assert first[0] == [0.0, pytest.approx(0.125)]  # wire B half a period after wire A
    assert first[1][0] == pytest.approx(0.125) and first[3][0] == 0.0  # trot
    with pytest.raises(ValueError, match="duty"):
        sequencer.SequencerParams(duty=1.0).check()

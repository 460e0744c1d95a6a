"""musclesim.cosim.interrupt: SIGINT and SIGTERM inside `interruptible` raise `Interrupted` (the
shell's exit code with it); inside a polled section they are only recorded."""
import os
import signal

import pytest

from musclesim.cosim import Interrupted, interruptible
from musclesim.cosim import interrupt


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_raises_interrupted_with_the_shells_exit_code(signum, code):
    before = signal.getsignal(signum)
    with pytest.raises(Interrupted) as err:
        with interruptible():
            os.kill(os.getpid(), signum)
    assert err.value.exit_code == code and err.value.results is None
    assert str(err.value) == f"interrupted by {signal.Signals(signum).name}"
    assert signal.getsignal(signum) == before  # the handler given back


def test_in_a_polled_section_a_signal_is_recorded_for_the_loop_to_act_on():
    with interruptible():
        with interrupt.polled():
            os.kill(os.getpid(), signal.SIGTERM)
            assert interrupt.requested() == signal.SIGTERM
    assert interrupt.requested() is None  # forgotten as the block ends

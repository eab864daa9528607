"""A stop request caught by an inner job reaches the job around it."""

import os
import signal

from softarm.interrupt import stop_on_signal


def test_a_signal_caught_inside_a_nested_block_reaches_the_enclosing_one():
    with stop_on_signal() as outer:
        with stop_on_signal() as inner:
            os.kill(os.getpid(), signal.SIGTERM)
        assert inner == [signal.SIGTERM]
        assert outer == [signal.SIGTERM]
    with stop_on_signal() as alone:
        pass
    assert alone == []

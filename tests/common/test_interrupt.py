"""Stop requests: one caught by an inner job reaches the job around it and the other way round; a second one
escalates."""

import os
import signal

import pytest

from softarm.interrupt import Escalated, stop_on_signal


def test_a_signal_caught_inside_a_nested_block_reaches_the_enclosing_one():
    with stop_on_signal() as outer:
        with stop_on_signal() as inner:
            os.kill(os.getpid(), signal.SIGTERM)
        assert inner == [signal.SIGTERM]
        assert outer == [signal.SIGTERM]
    with stop_on_signal() as alone:
        pass
    assert alone == []


def test_an_inner_block_starts_with_the_requests_its_outer_one_caught():
    with stop_on_signal() as outer:
        os.kill(os.getpid(), signal.SIGHUP)  # a closed terminal counts as a request too
        with stop_on_signal() as inner:
            assert inner == [signal.SIGHUP]
        assert outer == [signal.SIGHUP]  # passed on once, not twice


def test_a_second_request_escalates_at_once():
    with stop_on_signal() as caught:
        os.kill(os.getpid(), signal.SIGINT)
        with pytest.raises(Escalated):
            os.kill(os.getpid(), signal.SIGTERM)  # the handler runs before the next bytecode
    assert caught == [signal.SIGINT, signal.SIGTERM]

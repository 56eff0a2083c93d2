"""ros/diagnostics.age_status: a stream's status by its age. A role that subscribes when
its phase begins (issue 14: idle roles do not listen to 50 Hz odometry) is not in ERROR
for the moments before the first message arrives (diagnostics_paper saw 'no odometry
received yet' as an ERROR at the start of a healthy return), but is once the stream
stays silent beyond the stale bound."""
import pytest

from blind_navigation.ros import diagnostics


class Status(object):
    def summary(self, level, message):
        self.level, self.message = level, message

    def add(self, key, value):
        pass


def status(age, listening=None, stale=0.5):
    stat = Status()
    diagnostics.age_status(stat, 'odometry', age, stale, diagnostics.ERROR, listening=listening)
    return stat


def test_fresh_is_ok_and_stale_is_the_given_level():
    assert status(0.1).level == diagnostics.OK
    assert status(0.9).level == diagnostics.ERROR


@pytest.mark.parametrize('age', [None, 30.0])      # never heard, or heard before this subscription
def test_just_subscribed_and_nothing_yet_is_waiting(age):
    stat = status(age, listening=0.2)
    assert stat.level == diagnostics.OK and 'waiting for the first odometry' in stat.message


@pytest.mark.parametrize('age', [None, 30.0])
def test_silent_beyond_the_stale_bound_after_subscribing_is_an_error(age):
    assert status(age, listening=0.8).level == diagnostics.ERROR


def test_never_heard_without_knowing_when_it_subscribed_is_an_error():
    stat = status(None)
    assert stat.level == diagnostics.ERROR and 'no odometry received yet' in stat.message

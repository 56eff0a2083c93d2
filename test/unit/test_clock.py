"""ROS time that moves back (ros/clock.py), on a fake rospy clock: a sleep, a rate
or a timer that the time moving back (a restarted simulator's /clock) interrupts
returns how far it went back, warns once (naming the loop and the size), and
goes on; rospy's own raise ROSTimeMovedBackwardsException, which a loop took
for shutdown (the sampling publisher stopped taking samples) and a rospy.Timer
thread re-raised (a raw traceback)."""
import threading

import pytest
import rospy

from blind_navigation.ros import clock


class FakeRospy(object):
    """The part of rospy ros/clock.py uses, on a clock of its own: a sleep advances it,
    or, when :attr:`jump` is set, ends early with the time set back there and raises
    as rospy.sleep does."""
    ROSTimeMovedBackwardsException = rospy.ROSTimeMovedBackwardsException
    ROSInterruptException = rospy.ROSInterruptException

    def __init__(self):
        self.t = 10.0
        self.jump = None
        self.warnings = []
        self.lock = threading.Lock()
        fake = self

        class Rate(object):
            def __init__(self, hz):
                self.period, self.last_time = 1.0 / hz, fake.t

            def sleep(self):
                fake.sleep(max(0.0, self.last_time + self.period - fake.t))
                self.last_time += self.period
        self.Rate = Rate

    def get_time(self):
        return self.t

    get_rostime = get_time

    def sleep(self, seconds):
        with self.lock:
            start, jump, self.jump = self.t, self.jump, None
            if jump is None:
                self.t += seconds
                return
            self.t = jump
        raise rospy.ROSTimeMovedBackwardsException(start - jump)

    def is_shutdown(self):
        return False

    def logwarn(self, text, *args):
        self.warnings.append(text % args)


@pytest.fixture
def fake(monkeypatch):
    fake = FakeRospy()
    monkeypatch.setattr(clock, 'rospy', fake)
    return fake


def test_a_jump_back_ends_a_sleep_early_and_is_warned_once_with_its_size(fake):
    loop = clock.LoopClock('sampling', then='the sampling goes on')
    assert loop.sleep(1.0) == 0.0 and fake.t == 11.0 and fake.warnings == []
    fake.jump = 2.0
    assert loop.sleep(1.0) == pytest.approx(9.0)
    assert fake.warnings == ['sampling: the ROS time moved back 9.000 s (from 11.000 s to 2.000 s: a '
                             'restarted simulator, or a clock set back?); the sampling goes on']
    assert loop.sleep(1.0) == 0.0 and fake.t == 3.0 and len(fake.warnings) == 1
    assert loop.last_jump == (pytest.approx(9.0), 11.0, 2.0)


def test_a_jump_while_the_loop_worked_counts_at_its_next_sleep(fake):
    loop = clock.LoopClock('loop')
    loop.sleep(1.0)
    fake.t = 4.0                        # between two sleeps
    assert loop.sleep(0.5) == pytest.approx(7.0) and fake.t == 4.5
    assert len(fake.warnings) == 1


def test_jumps_close_together_are_warned_once_then_counted(fake, monkeypatch):
    wall = [100.0]
    monkeypatch.setattr(clock.time, 'monotonic', lambda: wall[0])
    loop = clock.LoopClock('loop')
    loop.sleep(1.0)
    for target in (5.0, 3.0):
        fake.jump = target
        loop.sleep(1.0)
    assert len(fake.warnings) == 1 and loop.moved_back == pytest.approx(6.0 + 2.0)
    wall[0] += clock.WARN_PERIOD
    fake.jump = 1.0
    loop.sleep(1.0)
    assert len(fake.warnings) == 2 and '(1 more jump(s) back before this one)' in fake.warnings[1]


def test_a_rate_goes_on_a_whole_period_from_the_jump(fake):
    rate = clock.LoopClock('loop').rate(2.0)
    assert rate.sleep() == 0.0 and fake.t == 10.5
    fake.jump = 1.0
    assert rate.sleep() == pytest.approx(9.5)
    assert rate.sleep() == 0.0 and fake.t == 1.5         # not 9.5 s of sleep to catch up


def test_every_goes_on_across_a_jump(fake):
    ticks, enough = [], threading.Event()
    fake.jump = 3.0

    def tick():
        ticks.append(fake.t)
        if len(ticks) == 3:
            enough.set()
    stop = clock.every(0.5, tick, 'periodic')
    assert enough.wait(5.0), 'the periodic timer stopped'
    stop.set()
    for thread in threading.enumerate():
        if thread.name == 'periodic':
            thread.join(5.0)            # before the fake goes
    assert ticks[:3] == [pytest.approx(t) for t in (3.0, 3.5, 4.0)]   # a period from the jump
    assert 'periodic: the ROS time moved back' in fake.warnings[0]

"""core/drive: the drive loop's per-cycle decision and typed outcomes."""
from types import SimpleNamespace

from blind_navigation.core import drive
from blind_navigation.core.allowance import HOLD

GRACE = SimpleNamespace(odom_timeout=0.4, odom_grace=1.0)


class Counting(drive.Behaviour):
    def __init__(self, steps):
        self.steps, self.held = steps, []

    def end(self):
        return drive.Outcome(drive.SUCCEEDED, '') if self.steps <= 0 else None

    def hold(self, seconds):
        self.held.append(seconds)

    def step(self, odom, now):
        self.steps -= 1
        return 0.1, 0.0


def test_end_comes_before_every_other_check():
    cycle = drive.DriveCycle(Counting(0), GRACE)
    decision, _ = cycle.decide(10.0, None, tripped='bumper', cancelled=True, inactive='x')
    assert decision == drive.Outcome(drive.SUCCEEDED, '') and decision.ok


def test_safety_then_cancel_then_preempted_in_that_order():
    cycle = drive.DriveCycle(Counting(5), GRACE)
    assert cycle.decide(1.0, 1.0, 'bumper', True, 'x')[0][:2] == (drive.SAFETY_STOP, 'bumper')
    assert cycle.decide(1.0, 1.0, None, True, 'x')[0].kind == drive.CANCELLED
    assert cycle.decide(1.0, 1.0, None, False, 'left')[0][:2] == (drive.PREEMPTED, 'left')
    assert cycle.decide(1.0, 1.0)[0] is None


def test_stale_odometry_holds_then_ends_after_the_grace_and_reports_the_hold():
    behaviour = Counting(5)
    cycle = drive.DriveCycle(behaviour, GRACE)
    decision, message = cycle.decide(1.0, 0.5)      # 0.5 s old: hold from 1.0
    assert decision == HOLD and 'holding (zero velocity)' in message
    assert cycle.decide(1.3, 0.5) == (HOLD, None)
    decision, message = cycle.decide(1.5, 1.45)      # fresh again: the hold ends
    assert decision is None and 'hold' in message
    assert behaviour.held == [0.5]
    cycle.decide(2.0, 1.0)                           # stale: a new hold from 2.0
    decision, message = cycle.decide(3.1, 1.0)
    assert decision.kind == drive.ODOMETRY_LOST and not decision.ok
    assert 'longer than odom_grace' in message


def test_without_a_grace_stale_odometry_ends_at_once():
    cycle = drive.DriveCycle(Counting(5), None, odom_timeout=0.4)
    assert cycle.decide(1.0, 0.7)[0] is None
    assert cycle.decide(1.0, 0.5)[0].kind == drive.ODOMETRY_LOST
    assert cycle.decide(1.0, None)[0].kind == drive.ODOMETRY_LOST

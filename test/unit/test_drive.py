"""core/drive.DriveCycle's odometry check; ros/drive_node.DriveNode's interruptions."""
from types import SimpleNamespace

from blind_navigation.core import drive, outcome
from blind_navigation.core.allowance import HOLD
from blind_navigation.ros.drive_node import DriveNode

GRACE = SimpleNamespace(odom_timeout=0.4, odom_grace=1.0)


def test_drive_node_ends_on_clock_then_safety_then_cancel_then_mission_left():
    """ros/drive_node.DriveNode's interruptions, in that order (the old DriveCycle's checks)."""
    node = SimpleNamespace(tripped=None, contacts=False, clock=SimpleNamespace(last_jump=(2.0, 5.0, 3.0)),
                           safety=SimpleNamespace(active=['bumper left pressed'], terminal=[]))
    ended = DriveNode._interrupted(node, 2.0, True, 'left')
    assert ended.kind == drive.FAILED and ended.cause == outcome.CLOCK
    assert DriveNode._interrupted(node, 0.0, True, 'x')[:2] == (drive.SAFETY_STOP,
                                                                'safety stop: bumper left pressed')
    node.contacts = True        # a contact pauses the drive: only a terminal event ends it
    assert DriveNode._interrupted(node, 0.0, True, 'x').kind == drive.CANCELLED
    assert DriveNode._interrupted(node, 0.0, False, 'left')[:2] == (drive.PREEMPTED, 'left')
    assert DriveNode._interrupted(node, 0.0, False, None) is None
    node.tripped = 'cliff'      # a trip between two cycles ends it though released since
    assert DriveNode._interrupted(node, 0.0, True, 'x')[:2] == (drive.SAFETY_STOP, 'safety stop: cliff')


def test_stale_odometry_holds_then_ends_after_the_grace_and_reports_the_hold():
    held = []
    cycle = drive.DriveCycle(GRACE, hold=held.append)
    decision, message = cycle.decide(1.0, 0.5)      # 0.5 s old: hold from 1.0
    assert decision == HOLD and 'holding (zero velocity)' in message
    assert cycle.decide(1.3, 0.5) == (HOLD, None)
    decision, message = cycle.decide(1.5, 1.45)      # fresh again: the hold ends
    assert decision is None and 'hold' in message
    assert held == [0.5]
    cycle.decide(2.0, 1.0)                           # stale: a new hold from 2.0
    decision, message = cycle.decide(3.1, 1.0)
    assert decision.kind == drive.ODOMETRY_LOST and not decision.ok
    assert 'longer than odom_grace' in message


def test_without_a_grace_stale_odometry_ends_at_once():
    cycle = drive.DriveCycle(None, odom_timeout=0.4)
    assert cycle.decide(1.0, 0.7)[0] is None
    assert cycle.decide(1.0, 0.5)[0].kind == drive.ODOMETRY_LOST
    assert cycle.decide(1.0, None)[0].kind == drive.ODOMETRY_LOST

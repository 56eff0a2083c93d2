"""The pi turn (core/rotation.Rotation) when its commands reach the base late: without
the pulses a turn hunted past its ``time_allowance`` from a 0.3 s lag on (the harness and
the ROS fake alike); now it settles within tolerance, and a turn that does not hunt
commands exactly what it did before."""
import math

import pytest

from blind_navigation.core.rotation import HUNTING, Rotation
from blind_navigation.sim import harness
from blind_navigation.sim.kobuki import CommandLag
from blind_navigation.sim.mission import Mission as Script

from unicycle import DT, Unicycle


def turn(lag, start_yaw=0.3):
    """A pi turn of an exact unicycle whose commands arrive ``lag`` s late: (rotation, robot)."""
    robot, rotation, late = Unicycle(yaw=start_yaw), Rotation(), CommandLag(lag)
    rotation.start(robot.odom)
    last = (0.0, 0.0)
    for _ in range(int(rotation.time_allowance / DT) + 100):
        command = rotation.step(robot.odom)
        if rotation.done or rotation.failed:
            break
        last = late.delay(robot.t, command) or last
        robot.move(last[0], last[1], DT)
    return rotation, robot


@pytest.mark.parametrize('lag', [0.3, 0.5, 0.8])
def test_a_late_base_is_turned_by_pi_in_pulses(lag):
    rotation, robot = turn(lag)
    assert rotation.done and not rotation.failed, 'the turn with a %.1f s lag did not settle' % lag
    assert rotation.reversals >= HUNTING and rotation.delay >= lag
    assert (robot.yaw - 0.3) % (2 * math.pi) == pytest.approx(math.pi, abs=2 * rotation.tolerance)


def test_a_turn_that_does_not_hunt_is_unchanged():
    rotation, robot = turn(0.0)
    assert rotation.done and rotation.reversals < HUNTING
    assert (robot.yaw - 0.3) % (2 * math.pi) == pytest.approx(math.pi, abs=rotation.tolerance)


def test_a_mission_on_a_late_base_comes_home_on_ground_truth():
    fast = Script([(0.0, 0.0, 1.0), (0.4, 0.0, 6.0)], name='fast_straight')
    played = harness.play(fast, 'paper', 'closed_loop', 0, turn_lag=0.5, command_lag=0.5)
    assert played.result.status == 'home', played.mission.reason
    assert played.result.position_error < 0.1

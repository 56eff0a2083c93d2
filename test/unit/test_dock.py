"""The fake's dock (sim/dock.py): the IR regions each receiver reports, the contacts, the
charger, the launch arg's poses; and kobuki_msgs' types (ros/kobuki_msgs_compat) with the
MD5 sums of kobuki_msgs' own definitions."""
import math

import pytest

from blind_navigation.core.geometry import Pose2D
from blind_navigation.ros import kobuki_msgs_compat as kobuki_msgs
from blind_navigation.sim import dock as d
from blind_navigation.sim.arena import ROBOT_RADIUS, Contacts

DOCK = d.Dock(Pose2D(0.0, 0.0, 0.0))
FACING = math.pi                      # a robot in front of DOCK faces it with this heading
#: genmsg's MD5 of kobuki_msgs' files (yujinrobot/kobuki_msgs noetic, ec50979; the action
#: expanded by actionlib_msgs' genaction.py): what a real robot's topics carry
REAL_MD5 = {
    'DockInfraRed': 'a3d77f7d15e50579473dcc24e9b97b34', 'SensorState': '430a4bfd78449c8740bfef32b26613a6',
    'AutoDockingAction': '44be114f3afc06365a090db0a5e982b5',
    'AutoDockingActionGoal': '4b30be6cd12b9e72826df56b481f40e0',
    'AutoDockingActionResult': '3fb2b9cd9cec6b4cb23b224521dd7679',
    'AutoDockingActionFeedback': '6f7132467beab5153587d9ebb8d8262d',
    'AutoDockingGoal': 'd41d8cd98f00b204e9800998ecf8427e', 'AutoDockingResult': '74697ed3d931f6eede8bf3a8dfeca160',
    'AutoDockingFeedback': '03343b6aa0067ce6251bcc08bf318388',
    'BumperEvent': 'ffe360cd50f14f9251d9844083e72ac5',
}


@pytest.mark.parametrize('name', sorted(REAL_MD5))
def test_kobuki_types_carry_the_real_md5_sums(name):
    cls = getattr(kobuki_msgs, name, None) or kobuki_msgs._CLASSES[name]
    assert (cls._type, cls._md5sum) == ('kobuki_msgs/' + name, REAL_MD5[name])


def test_the_bit_constants_are_kobuki_msgs():
    ir = kobuki_msgs.DockInfraRed
    assert (ir.NEAR_LEFT, ir.NEAR_CENTER, ir.NEAR_RIGHT, ir.FAR_LEFT, ir.FAR_CENTER, ir.FAR_RIGHT) == (
        d.NEAR_LEFT, d.NEAR_CENTER, d.NEAR_RIGHT, d.FAR_LEFT, d.FAR_CENTER, d.FAR_RIGHT)
    state = kobuki_msgs.SensorState
    assert (state.DOCKING_CHARGING, state.DOCKING_CHARGED, state.DISCHARGING) == (d.CHARGING, d.CHARGED,
                                                                                   d.DISCHARGING)


@pytest.mark.parametrize('u, v, bits', [
    (1.0, 0.0, d.NEAR_CENTER | d.FAR_CENTER),
    (1.0, 0.5, d.NEAR_LEFT | d.FAR_LEFT),                 # the dock's left: +v
    (1.0, -0.5, d.NEAR_RIGHT | d.FAR_RIGHT),
    (4.0, 0.0, d.FAR_CENTER), (4.0, 0.5, d.FAR_LEFT),     # beyond the near field: far bits only
    (1.0, 0.04, d.NEAR_CENTER | d.FAR_CENTER | d.NEAR_LEFT | d.FAR_LEFT),   # regions overlap at borders
    (6.0, 0.0, 0), (1.0, 1.5, 0), (-0.5, 0.0, 0),        # beyond range, aside, behind
])
def test_regions(u, v, bits):
    assert d.regions(u, v) == bits


def test_the_central_receiver_sees_the_region_it_is_in_when_facing_the_dock():
    assert DOCK.ir(Pose2D(1.5, 0.0, FACING)) == [0, d.NEAR_CENTER | d.FAR_CENTER, 0]
    assert DOCK.ir(Pose2D(3.5, 0.6, FACING)) == [0, d.FAR_LEFT, 0]
    assert DOCK.ir(Pose2D(1.5, 0.0, 0.0)) == [0, 0, 0]              # facing away: nothing


def test_a_side_receiver_sees_the_dock_beside_the_robot():
    # on the dock's left, heading for the axis (-v): the dock is on the robot's right
    right, mid, left = DOCK.ir(Pose2D(1.0, 0.5, -math.pi / 2 - math.radians(30.0)))
    assert right == d.NEAR_LEFT | d.FAR_LEFT and mid == left == 0


def test_contacts_on_the_axis_dock_elsewhere_bump():
    assert DOCK.contact(DOCK.docked_pose()) == d.DockContact(True, 0)
    assert DOCK.contact(Pose2D(ROBOT_RADIUS, 0.03, FACING + 0.1)).docked
    assert DOCK.contact(Pose2D(ROBOT_RADIUS + 0.05, 0.0, FACING)) == d.DockContact(False, 0)
    angled = Pose2D(ROBOT_RADIUS * math.cos(0.6), 0.1, FACING + 0.6)    # front at the face, 34 deg off
    assert DOCK.contact(angled) == d.DockContact(False, d.BUMPER_CENTRE)
    assert DOCK.contact(Pose2D(ROBOT_RADIUS, 0.5, FACING)) == d.DockContact(False, 0)   # beside the dock


def test_charger_and_bumper_bits():
    assert [d.charger_state(False, 16.0), d.charger_state(True, 16.0), d.charger_state(True, 16.6)] == [
        d.DISCHARGING, d.CHARGING, d.CHARGED]
    assert d.bumper_bits(Contacts(frozenset({'left', 'right'}), frozenset(), frozenset())) == 5
    assert d.bumper_bits(None) == 0


def test_the_start_dock_is_behind_the_robot_backed_off_and_turned_away():
    start = Pose2D(1.0, 2.0, math.pi / 2)
    dock = d.dock_from_spec('start', start)
    gap = ROBOT_RADIUS + d.UNDOCK_BACKOFF
    assert dock.pose == pytest.approx((1.0, 2.0 - gap, math.pi / 2))
    assert dock.to_dock(start.x, start.y) == pytest.approx((gap, 0.0))


@pytest.mark.parametrize('spec, pose', [('1 -1.5 3.14', (1.0, -1.5, 3.14)), ('0,1.5,0', (0.0, 1.5, 0.0))])
def test_a_dock_pose_from_the_launch_arg(spec, pose):
    assert d.dock_from_spec(spec).pose == pytest.approx(pose)
    assert d.dock_from_spec('none') is None and d.dock_from_spec('') is None


@pytest.mark.parametrize('spec', ['here', '1 2', '1 nan 0'])
def test_a_bad_dock_arg_is_refused(spec):
    with pytest.raises(ValueError, match='dock'):
        d.dock_from_spec(spec)

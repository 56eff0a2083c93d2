"""A docking run in plain Python: :class:`sim.dock_drive.DockDrive` on a simulated base before a dock.

The fake's action server (sim/nodes/fake_dock_drive.py) ends a goal by :func:`verdict`;
:func:`run_docking` plays a whole goal on a base (kinematic or MuJoCo) without ROS, as the
unit tests and a bench do: the IR, bumper and charger from sim/dock.py each 50 Hz cycle;
:func:`dock_mission` plays it for a mission in ``docking`` (sim/harness.py, dock_at_home).
"""
import math
from collections import namedtuple

from ..core.docking import DOCK, DockingResult as MissionDocking
from ..core.mission import Inputs
from .dock import DockContact, charger_state
from .dock_drive import DockDrive
from .kobuki import SENSOR_PERIOD

TIME_LIMIT = 120.0            # s of sim time a goal may take (the fake's; docs/fake_turtlebot.md)
LOST_TIME = 5.0               # s driving with no receiver seeing any beam: the dock is lost (the fake's)
#: bumps without charging that end a goal once backed off: the drive's retry after a bump re-aligns
#: on the same beam 1 cm back, so a second bump is the same approach again (docs/fake_turtlebot.md)
BUMP_LIMIT = 2
SUCCEEDED = 'Arrived on docking station successfully.'   # kobuki_auto_docking's result text

DockingResult = namedtuple('DockingResult', 'docked text state time farthest')
DockingResult.__doc__ = ('docked: the goal succeeded; text: the result text; state: the dock drive\'s '
                         'last state; time: s of sim time; farthest: m from the start at most.')


def verdict(drive, elapsed, time_limit=TIME_LIMIT):
    """None while the goal goes on, else (succeeded, result text)."""
    if drive.done:
        return True, SUCCEEDED
    if drive.state == 'UNKNOWN':
        return False, 'Aborted: dock not seen: no dock IR beam found in a full turn (state UNKNOWN).'
    if drive.bumped >= BUMP_LIMIT and drive.state != 'BUMPED':
        return False, 'Aborted: bumped %d times without charging, backed off (state %s).' % (
            drive.bumped, drive.state)
    if drive.unseen_time > LOST_TIME:
        return False, 'Aborted: dock lost: no dock IR beam for %g s while driving (state %s).' % (
            LOST_TIME, drive.state)
    if elapsed > time_limit:
        return False, 'Aborted: not docked within the time limit of %g s (state %s).' % (time_limit, drive.state)
    return None


def run_docking(base, dock, time_limit=TIME_LIMIT, battery=16.0):
    """Play one docking goal on ``base`` (SimulatedKobuki or MujocoKobuki) before ``dock``
    (sim/dock.Dock) until :func:`verdict` ends it; the base is left standing."""
    drive, start, elapsed, farthest = DockDrive(), base.true_pose, 0.0, 0.0
    while True:
        pose = base.true_pose
        farthest = max(farthest, math.hypot(pose.x - start.x, pose.y - start.y))
        contact = dock.contact(pose)
        v, w = drive.update(dock.ir(pose), contact.bumper, charger_state(contact.docked, battery),
                            base.odom.yaw)
        ended = verdict(drive, elapsed, time_limit)
        if ended is not None:
            base.command(0.0, 0.0)
            return DockingResult(ended[0], ended[1], drive.state, elapsed, farthest)
        base.command(v, w)
        base.step(SENSOR_PERIOD)
        elapsed += SENSOR_PERIOD


def dock_mission(run, mission, time_limit=TIME_LIMIT, battery=16.0):
    """Step ``mission`` (core/mission.Mission in ``docking``) on ``run`` (sim/harness's, its ``dock``
    a sim/dock.Dock or None) while the dock drive plays its goal, as the fake's action server does,
    the goal's end given as ``Inputs.docking``; the DockingResult (farthest: m from the arrival)."""
    base, drive, elapsed, farthest, ended = run.base, DockDrive(), 0.0, 0.0, None
    start, state = base.true_pose, 'IDLE'
    while mission.phase == DOCK:
        outcome = None
        if drive is not None:
            pose = base.true_pose
            contact = run.dock.contact(pose) if run.dock else DockContact(False, 0)
            v, w = drive.update(run.dock.ir(pose) if run.dock else [0, 0, 0], contact.bumper,
                                charger_state(contact.docked, battery), base.odom.yaw)
            ended, state = verdict(drive, elapsed, time_limit), drive.state
            if ended is not None:
                v, w, drive, outcome = 0.0, 0.0, None, MissionDocking(*ended)
            base.command(v, w)
        run.advance()
        elapsed += run.dt
        pose = base.true_pose
        farthest = max(farthest, math.hypot(pose.x - start.x, pose.y - start.y))
        mission.step(base.t, Inputs(odom=base.odom, docking=outcome))
    base.command(0.0, 0.0)
    docked = ended is not None and ended[0]
    return DockingResult(docked, ended[1] if ended else mission.reason, state, elapsed, farthest)

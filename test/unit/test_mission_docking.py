"""dock_at_home in the harness and the core: a mission starting at its dock ends ``docked`` on
the charging contacts (ground truth); a dock moved 1.5 m aside ends ``home`` naming 'dock not
seen' without wandering; during ``docking`` the mission publishes nothing, asks for the goal
once, and ends home on a failure, a takeover or its allowance, aborted on cancel or a cliff."""
import copy
import math

import pytest

from blind_navigation.core import mission_state as ms, outcome
from blind_navigation.core.docking import DOCK, DockingResult
from blind_navigation.core.geometry import Pose2D
from blind_navigation.core.mission import Inputs
from blind_navigation.sim import harness
from blind_navigation.sim.dock import CHARGING, Dock, charger_state
from blind_navigation.sim.harness import play

from test_dock_drive import BASES  # noqa: E402 (kinematic, and mujoco where it is installed)

MISSION = 'table6_test1'        # 2.6 m, 30 s of driving
ASIDE = 1.5                     # m the dock is moved sideways (issue 31)
#: m the robot may move while the dock drive looks for an unseen dock: it turns on the spot
#: (a scan of a full turn), so only the robot's own turning slip moves its centre
NO_WANDERING = 0.1


def _play(**settings):
    return play(MISSION, 'paper', 'closed_loop', 0, floor=False, dock_at_home=True, **settings)


def _states(played):
    return [new for _, _, new, _ in played.mission.transitions]


@pytest.mark.parametrize('base', BASES)
def test_a_mission_that_started_on_its_dock_ends_docked_on_the_charger(base):
    played = _play(dock='start', base=base)
    assert _states(played)[-3:] == [ms.RETURNING, ms.DOCKING, ms.DOCKED]
    assert played.result.status == ms.DOCKED
    assert 'docked on the charger' in played.mission.reason
    assert played.mission.machine.outcome == outcome.DOCKED
    assert 'from the start by odometry' in played.mission.reason     # the return's verdict kept
    contact = played.run.dock.contact(played.run.base.true_pose)
    assert contact.docked and charger_state(contact.docked, 16.0) == CHARGING
    assert played.run.docking.docked and played.run.docking.time < 60.0


def test_without_dock_at_home_nothing_changes():
    played = play(MISSION, 'paper', 'closed_loop', 0, floor=False, dock='start')
    assert _states(played)[-1] == ms.HOME and ms.DOCKING not in _states(played)
    assert played.run.docking is None


def test_a_dock_moved_aside_ends_home_naming_it_without_wandering():
    start = Dock.behind(Pose2D(0.0, 0.0, 0.0)).pose
    played = _play(dock=Dock(Pose2D(start.x, start.y + ASIDE, start.yaw)))
    assert _states(played)[-2:] == [ms.DOCKING, ms.HOME]
    reason = played.mission.reason
    assert reason.startswith('docking failed: ') and 'dock not seen' in reason, reason
    assert 'from the start by odometry' in reason
    assert played.mission.machine.outcome == outcome.DOCK_FAILED
    assert not played.run.docking.docked and played.run.docking.farthest < NO_WANDERING
    for _ in range(100):            # 2 s with no new command: the base was left commanded zero
        played.run.advance()
    assert math.hypot(*played.run.base.true_twist) < 1e-3


@pytest.fixture(scope='module')
def docking(request):
    """A copy of the mission as it entered ``docking`` (the harness's docking is stubbed)."""
    kept = []
    original = harness.dock_mission
    harness.dock_mission = lambda run, mission, **_: kept.append(copy.deepcopy(mission))
    try:
        _play(dock='start')
    finally:
        harness.dock_mission = original
    return kept[0]


def _step(mission, **inputs):
    return mission.step(mission.now + 0.02, Inputs(**inputs))


def test_in_docking_the_goal_is_asked_for_once_and_nothing_is_published(docking):
    mission = copy.deepcopy(docking)
    assert mission.phase == DOCK and mission.state == ms.DOCKING
    steps = [_step(mission) for _ in range(3)]
    assert [step.command for step in steps] == [None] * 3
    assert [step.dock for step in steps] == [False] * 3     # asked on the step that entered docking
    assert mission.drive.start is False


@pytest.mark.parametrize('inputs,state,code,words', [
    (dict(docking=DockingResult(True, 'Arrived on docking station successfully.')), ms.DOCKED,
     outcome.DOCKED, 'docked on the charger (Arrived'),
    (dict(docking=DockingResult(False, 'Aborted: dock lost')), ms.HOME, outcome.DOCK_FAILED,
     'docking failed: Aborted: dock lost'),
    (dict(operator='operator takeover by /teleop'), ms.HOME, outcome.DOCK_FAILED,
     'docking failed: operator takeover by /teleop'),
    (dict(tripped='cliff left'), ms.ABORTED, outcome.SAFETY_EVENT, 'the docking: safety stop: cliff left'),
])
def test_a_docking_ends_by_its_result_a_takeover_or_a_cliff(docking, inputs, state, code, words):
    mission = copy.deepcopy(docking)
    step = _step(mission, **inputs)
    assert (step.state, step.command, mission.machine.outcome) == (state, (0.0, 0.0), code)
    assert words in mission.reason


def test_a_docking_ends_home_past_its_allowance_and_aborted_on_cancel(docking):
    late = copy.deepcopy(docking)
    late.step(late.drive.started + late.drive.timeout - 0.5, Inputs())
    assert late.state == ms.DOCKING
    late.step(late.drive.started + late.drive.timeout + 0.5, Inputs())
    assert late.state == ms.HOME and 'not docked within 180 s' in late.reason
    assert late.machine.outcome == outcome.DOCK_FAILED
    cancelled = copy.deepcopy(docking)
    assert cancelled.cancel() is None
    assert cancelled.state == ms.ABORTED and cancelled.reason.startswith(ms.CANCELLED)
    assert cancelled.machine.outcome == outcome.CANCELLED

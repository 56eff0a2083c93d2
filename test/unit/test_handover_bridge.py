"""closed_loop between two goals (core/goal.HandoverBridge, back_travel_server and the
harness): the return's shared follower goes on driving the route while the next goal
comes, for at most handover_follow, so the commands stay continuous across hand-overs
(on ROS each costs an action round trip: 0.04-0.30 s sim at the median at rtf 5, longer
than CommandHold's 0.1 s, so the robot stopped and started again at most hand-overs)."""
import types

import pytest

from blind_navigation.core.goal import HandoverBridge, SectionGoal, bridges, make_goal
from blind_navigation.sim import harness
from blind_navigation.sim.harness import run_mission


class _Follower(object):
    def __init__(self, started=True):
        self.started, self.done, self.failed, self.travelled, self.steps = started, False, False, 0.0, 0

    def step(self, odom):
        self.steps += 1
        self.travelled += 0.004
        return 0.2, 0.1


def test_the_bridge_steps_the_follower_until_its_time_is_over():
    follower = _Follower()
    bridge = HandoverBridge(follower, 0.5, now=10.0)
    assert bridge.step(None) == (0.2, 0.1) and follower.steps == 1
    assert not bridge.expired(10.49) and bridge.expired(10.5)
    follower.done = True                     # the route finished: nothing more to drive
    assert bridge.ended and bridge.step(None) == (0.0, 0.0) and follower.steps == 1
    with pytest.raises(ValueError, match='handover_follow'):
        HandoverBridge(follower, 0.0, now=0.0)


def test_only_closed_loop_bridges_and_only_between_two_goals_of_a_moving_follower():
    follower = _Follower()
    assert bridges('closed_loop', follower, 1, 5) and bridges('closed_loop', follower, 4, 5)
    assert not bridges('closed_loop', follower, 5, 5)        # after the last goal: the final hold
    assert not bridges('closed_loop', follower, 0, 5)
    assert not bridges('closed_loop', follower, 2, 5, follow=0.0)   # off: the hold, as before
    assert not bridges('time', follower, 2, 5) and not bridges('closed_loop', None, 2, 5)
    assert not bridges('closed_loop', _Follower(started=False), 2, 5)
    follower.failed = True
    assert not bridges('closed_loop', follower, 2, 5)


def test_what_the_bridge_drove_counts_to_the_next_goal():
    follower = _Follower()
    follower.travelled = 1.0
    follower.section_finished = lambda index: False
    goal = make_goal('closed_loop', None, None, follower, 3, since=0.9)
    assert isinstance(goal, SectionGoal)
    goal.start(types.SimpleNamespace())
    assert goal.travelled == pytest.approx(0.1)
    plain = make_goal('closed_loop', None, None, follower, 3)
    plain.start(types.SimpleNamespace())
    assert plain.travelled == 0.0


_ADVANCE, _RETURN = harness._Run.advance, harness._return


def _return_commands(monkeypatch, **settings):
    """The commands the base got from the return's start to its end, per control step."""
    commands, returning = [], []
    advance, back = _ADVANCE, _RETURN

    def traced(run, command=None):
        if returning and command is not None:
            commands.append(command)
        advance(run, command)

    def traced_return(*args, **kwargs):
        returning.append(True)
        try:
            return back(*args, **kwargs)
        finally:
            returning.pop()
    monkeypatch.setattr(harness._Run, 'advance', traced)
    monkeypatch.setattr(harness, '_return', traced_return)
    result = run_mission('table6_test1', 'paper', 'closed_loop', 0, floor=False, **settings)
    return result, commands


def _zeros(commands):
    return sum(1 for command in commands if command == (0.0, 0.0))


def test_slow_hand_overs_no_longer_stop_the_robot(monkeypatch):
    quick, quick_commands = _return_commands(monkeypatch)
    slow, slow_commands = _return_commands(monkeypatch, handover_latency=0.2)
    held, held_commands = _return_commands(monkeypatch, handover_latency=0.2, handover_follow=0.0)
    hand_overs = len(slow.landmarks) - 1
    assert quick.status == slow.status == held.status == 'home'
    # bridged, a 0.2 s hand-over drives as no hand-over does: the same commands, time, error
    assert slow_commands == quick_commands
    assert slow.return_time == pytest.approx(quick.return_time, abs=0.03)
    assert slow.position_error == pytest.approx(quick.position_error, abs=1e-6)
    # holding 0.1 s, then zero (the paper modes' hold): 0.1 s of zero at each hand-over
    zero_steps = _zeros(held_commands) - _zeros(quick_commands)
    assert zero_steps >= hand_overs * 0.1 / harness.SIMULATION_DEFAULTS['control_dt'] - 1
    assert held.return_time - quick.return_time > hand_overs * 0.1

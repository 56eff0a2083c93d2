"""The output between two goals (core/goal.CommandHold, back_travel_server and the
harness): the last command holds at most handover_timeout after a goal last
published, and a goal that ends as it starts does not renew it. On ROS every
goal costs an action round trip; a run of such goals (the landmarks of a loop
the route cut) kept the approach speed going past the corner for as long as the
run took (the harness's ``handover_latency``): the robot overshot the junction,
turned back, and the goal took twice as long (mission_gap_in_return aborted once
on the client's per-goal backstop)."""
import pytest

from blind_navigation.core.goal import CommandHold
from blind_navigation.sim.harness import run_mission

HANDOVER = 0.1


def test_the_last_command_holds_for_the_handover_timeout_after_it_was_published():
    hold = CommandHold(HANDOVER)
    assert hold.expired(0.0)                        # nothing published: nothing to hold
    hold.published(10.0)
    assert not hold.expired(10.05) and hold.remaining(10.05) == pytest.approx(0.05)
    assert hold.expired(10.1) and hold.remaining(10.3) == 0.0


def test_only_publishing_renews_the_hold():
    hold = CommandHold(HANDOVER)
    hold.published(10.0)
    # goals that end as they start publish nothing: however many of them come, the
    # hold ends handover_timeout after the last command
    assert hold.expired(10.0 + 12 * 0.05)
    hold.published(10.7)
    assert not hold.expired(10.75)


def test_a_clock_that_moved_back_ends_the_hold():
    hold = CommandHold(HANDOVER)
    hold.published(60.0)
    # a restarted /clock: how long the command held is unknown, so it holds no longer
    assert hold.expired(0.05) and hold.remaining(0.05) == 0.0


def test_a_bad_timeout_is_refused():
    with pytest.raises(ValueError, match='handover_timeout'):
        CommandHold(0.0)


@pytest.mark.parametrize('seed', [0, 1])
def test_slow_hand_overs_cost_their_own_time_not_a_detour(seed):
    # real_back_out: the route cuts the reversed stretch; the goals of its landmarks
    # end as they start, at the junction, where the follower stops and turns
    settings = dict(event_sampling=True, prune_loops=True, floor=False)
    quick = run_mission('real_back_out', 'paper', 'closed_loop', seed, **settings)
    slow = run_mission('real_back_out', 'paper', 'closed_loop', seed, handover_latency=0.125, **settings)
    assert quick.status == slow.status == 'home', slow.reason
    hand_overs = len(slow.landmarks) - 1
    assert slow.return_time - quick.return_time < hand_overs * 0.125 + 1.0
    assert slow.position_error < 0.02 * slow.distance

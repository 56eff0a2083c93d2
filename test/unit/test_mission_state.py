"""core/mission_state.MissionState: every legal transition moves, illegal ones raise,
a transition from a state the mission is not in does not move, terminal states change
only to idle (new_mission), and two threads racing the same transition: exactly one wins."""
import threading
import time

import pytest

from blind_navigation.core import mission_state as ms, outcome

LEGAL = [(old, new) for old, targets in ms.TRANSITIONS.items() for new in targets]
ILLEGAL = [(old, new) for old in ms.TRANSITIONS for new in ms.ALL + (None,)
           if new not in ms.TRANSITIONS[old]]


class SlowRead(ms.MissionState):
    """Reading the state yields the thread: a check-then-set without the lock loses the race."""

    @property
    def state(self):
        value = self._value
        time.sleep(0.0005)
        return value

    @state.setter
    def state(self, value):
        self._value = value


def in_state(state, cls=ms.MissionState):
    machine = cls()
    machine.state = state       # the test's set-up only: the product moves by transition()
    return machine


def test_the_table_names_every_state_and_the_start():
    assert set(ms.TRANSITIONS) == set(ms.ALL) | {None}
    assert all(set(targets) <= set(ms.ALL) for targets in ms.TRANSITIONS.values())
    assert len(LEGAL) == 19 + len(ms.TERMINAL)     # recording -> home: nothing to retrace; docking
    assert all(ms.TRANSITIONS[ended] == (ms.IDLE,) for ended in ms.TERMINAL)


@pytest.mark.parametrize('old,new', LEGAL)
def test_every_legal_transition_moves(old, new):
    machine = in_state(old)
    assert machine.transition(old, new, 'why') is True
    assert (machine.state, machine.reason) == (new, 'why')


@pytest.mark.parametrize('old,new', ILLEGAL)
def test_an_illegal_transition_raises_and_changes_nothing(old, new):
    machine = in_state(old)
    with pytest.raises(ms.IllegalTransition, match='%s -> %s' % (old, new)):
        machine.transition(old, new)
    assert machine.state == old


def test_a_transition_from_another_state_does_not_move():
    machine = in_state(ms.ABORTED)
    assert machine.transition(ms.ROTATING, ms.RETURNING) is False
    assert machine.state == ms.ABORTED


@pytest.mark.parametrize('old', [None, ms.IDLE, ms.RECORDING, ms.ROTATING, ms.RETURNING, ms.DOCKING])
def test_abort_ends_every_unfinished_state(old):
    machine = in_state(old)
    assert machine.abort('fault', outcome.ROLE_FAILURE) == (True, old)
    assert (machine.state, machine.reason, machine.outcome) == (ms.ABORTED, 'fault',
                                                                outcome.ROLE_FAILURE)


@pytest.mark.parametrize('old', ms.TERMINAL)
def test_abort_leaves_an_ended_mission_alone(old):
    machine = in_state(old)
    code = machine.outcome
    assert machine.abort('late fault', outcome.ROLE_FAILURE) == (False, old)
    assert (machine.state, machine.reason, machine.outcome) == (old, '', code)


@pytest.mark.parametrize('second', [ms.RETURNING, ms.ABORTED])
def test_two_threads_racing_a_transition_exactly_one_wins(second):
    for _ in range(100):
        machine = in_state(ms.ROTATING, SlowRead)
        start = threading.Barrier(2)
        won = []

        def race(new):
            start.wait(5.0)
            won.append((new, machine.transition(ms.ROTATING, new)))

        threads = [threading.Thread(target=race, args=(new,)) for new in (ms.RETURNING, second)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(5.0)
            assert not thread.is_alive(), 'a racing transition did not return within 5 s'
        winners = [new for new, moved in won if moved]
        assert len(winners) == 1, won
        assert machine.state == winners[0]


def test_abort_racing_a_transition_leaves_one_consistent_end():
    for _ in range(100):
        machine = in_state(ms.RETURNING, SlowRead)
        start = threading.Barrier(2)
        results = {}

        def home():
            start.wait(5.0)
            results['home'] = machine.transition(ms.RETURNING, ms.HOME, 'home', outcome.HOME)

        def abort():
            start.wait(5.0)
            results['abort'] = machine.abort('fault', outcome.ROLE_FAILURE)[0]

        threads = [threading.Thread(target=home), threading.Thread(target=abort)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(5.0)
        assert results['home'] != results['abort'], results
        assert (machine.state, machine.outcome) == ((ms.HOME, outcome.HOME) if results['home'] else
                                                    (ms.ABORTED, outcome.ROLE_FAILURE))


def test_go_home_starts_the_return_only_while_recording():
    assert ms.go_home_refusal(ms.RECORDING) is None
    for other in (None,) + tuple(s for s in ms.ALL if s != ms.RECORDING):
        refusal = ms.go_home_refusal(other)
        assert refusal.startswith('refused: the mission is %s ' % other), refusal


def test_cancel_aborts_every_unfinished_state_and_refuses_an_ended_one():
    for unfinished in (ms.IDLE, ms.RECORDING, ms.ROTATING, ms.RETURNING):
        assert ms.cancel_refusal(unfinished) is None
        machine = ms.MissionState()
        machine.state = unfinished
        assert machine.abort(ms.CANCELLED, outcome.CANCELLED) == (True, unfinished)
        assert (machine.state, machine.reason, machine.outcome) == (ms.ABORTED, 'cancelled by request',
                                                                    outcome.CANCELLED)
    for ended in ms.TERMINAL + (None,):
        assert ms.cancel_refusal(ended).startswith('refused: the mission is %s ' % ended)


def test_vision_back_moves_are_in_the_table():
    """Before the turn back to recording (a brief loss); in the turn or the return, with
    on_vision_back stop, recovered (the policies: test_mission_harness*)."""
    ms.check_transition(ms.ROTATING, ms.RECORDING)
    for current in (ms.ROTATING, ms.RETURNING):
        ms.check_transition(current, ms.RECOVERED)


def test_recovered_is_terminal_and_nobody_moves_in_it():
    assert ms.RECOVERED in ms.TERMINAL and not ms.records(ms.RECOVERED)
    assert not any(ms.may_move(role, ms.RECOVERED) for role in (ms.ROTATION_ROLE, ms.BACK_TRAVEL_ROLE))
    with pytest.raises(ms.IllegalTransition):
        ms.check_transition(ms.RECOVERED, ms.RECORDING)
    machine = ms.MissionState()
    for old, new in ((None, ms.IDLE), (ms.IDLE, ms.RECORDING), (ms.RECORDING, ms.ROTATING),
                     (ms.ROTATING, ms.RETURNING), (ms.RETURNING, ms.RECOVERED)):
        assert machine.transition(old, new, '', outcome.VISION_BACK)
        assert machine.outcome == (outcome.VISION_BACK if new in ms.TERMINAL else outcome.NONE)
    assert machine.abort('late', outcome.ROLE_FAILURE) == (False, ms.RECOVERED)
    assert machine.outcome == outcome.VISION_BACK
    assert machine.transition(ms.RECOVERED, ms.IDLE) and machine.outcome == outcome.NONE


def test_the_recording_goes_on_while_rotating_until_the_owner_ends_it():
    assert ms.records(ms.ROTATING) and not ms.records(ms.RETURNING)
def test_new_mission_starts_from_every_terminal_state_and_is_refused_elsewhere():
    for ended in ms.TERMINAL:
        assert ms.new_mission_refusal(ended) is None
        machine = in_state(ended)
        assert machine.transition(ended, ms.IDLE, 'mission 2')
        assert (machine.state, machine.reason) == (ms.IDLE, 'mission 2')
        assert ms.starts_new_mission(ended, ms.IDLE)
    for unfinished in (None, ms.IDLE, ms.RECORDING, ms.ROTATING, ms.RETURNING):
        refusal = ms.new_mission_refusal(unfinished)
        assert refusal.startswith('refused: the mission is %s ' % unfinished), refusal
        for ended in ms.TERMINAL:
            assert ended in refusal
        assert not ms.starts_new_mission(unfinished, ms.IDLE)
    for unfinished in (ms.IDLE, ms.RECORDING, ms.ROTATING, ms.RETURNING):
        with pytest.raises(ms.IllegalTransition):       # a mission under way never restarts
            in_state(unfinished).transition(unfinished, ms.IDLE)
    assert not ms.starts_new_mission(ms.HOME, ms.RECORDING)

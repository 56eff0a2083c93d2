"""ros/mission.MissionStateView (no master: its subscription is replaced): a role that
registers once the state is known learns it at once as (None, state) (finding 7: a
rotate_pi restarted mid-turn registered after the latched 'rotating' arrived and never
heard of it: the mission hung until the client's rotation timeout), and every role
sees the changes once each, in order, however registration and changes race."""
import threading

import pytest

from blind_navigation.ros import mission


@pytest.fixture
def view(monkeypatch):
    monkeypatch.setattr(mission, 'subscribe', lambda *args, **kwargs: None)
    return mission.MissionStateView('/owner', guard=lambda fn: fn)


def test_a_role_registered_after_the_state_came_learns_it_at_once(view):
    view.set_local('rotating')
    seen = []
    view.on_change(lambda old, new: seen.append((old, new)))
    assert seen == [(None, 'rotating')]
    view.set_local('aborted')
    assert seen == [(None, 'rotating'), ('rotating', 'aborted')]


def test_a_role_registered_before_any_state_hears_only_changes(view):
    seen = []
    view.on_change(lambda old, new: seen.append((old, new)))
    assert seen == []
    view.set_local('idle')
    view.set_local('idle')
    assert seen == [(None, 'idle')]


def test_racing_registrations_and_changes_deliver_each_state_once_in_order(view):
    walk = ['idle', 'recording', 'rotating', 'returning', 'home']
    logs = [[] for _ in range(20)]
    start = threading.Barrier(len(logs) + 1)

    def register(log):
        start.wait()
        view.on_change(lambda old, new: log.append((old, new)))

    threads = [threading.Thread(target=register, args=(log,)) for log in logs]
    for thread in threads:
        thread.start()
    start.wait()
    for state in walk:
        view.set_local(state)
    for thread in threads:
        thread.join()
    for log in logs:
        news = [new for _, new in log]
        assert news == walk[walk.index(news[0]):], log      # a suffix of the walk, no repeats
        assert log[0][0] is None
        assert all(old == previous for (old, _), (_, previous) in zip(log[1:], log))

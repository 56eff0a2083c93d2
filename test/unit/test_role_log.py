"""ros/common.RoleLog.warn_throttle, without a master: each role's and each text's
warning is throttled on its own (rospy's throttle keys on the calling line, which
RoleLog's one line would share between every role and text)."""
import pytest

rospy = pytest.importorskip('rospy')

from blind_navigation.ros import common  # noqa: E402


@pytest.fixture
def warned(monkeypatch):
    """The warnings logged, and the clock (``clock[0]``, s) the throttle reads."""
    lines, clock = [], [100.0]
    monkeypatch.setattr(common.rospy, 'get_time', lambda: clock[0])
    monkeypatch.setattr(common.rospy, 'logwarn', lambda text, *args: lines.append(text % args))
    return lines, clock


def test_two_roles_and_two_texts_are_throttled_apart(warned):
    lines, clock = warned
    server, turn = common.RoleLog('node/server'), common.RoleLog('node/rotate_pi')
    for _ in range(3):
        server.warn_throttle(5.0, 'odometry %d s old', 1)
        server.warn_throttle(5.0, 'no route')
        turn.warn_throttle(5.0, 'odometry %d s old', 2)
    assert lines == ['node/server: odometry 1 s old', 'node/server: no route',
                     'node/rotate_pi: odometry 2 s old']


def test_a_text_comes_again_after_its_period_or_when_time_moves_back(warned):
    lines, clock = warned
    log = common.RoleLog('node/server')
    log.warn_throttle(5.0, 'no route')
    clock[0] = 104.9
    log.warn_throttle(5.0, 'no route')
    assert len(lines) == 1, 'logged again within its 5 s: %r' % lines
    clock[0] = 105.0
    log.warn_throttle(5.0, 'no route')
    clock[0] = 1.0                  # the sim clock restarted
    log.warn_throttle(5.0, 'no route')
    assert len(lines) == 3, 'not logged again after 5 s and after time moved back: %r' % lines

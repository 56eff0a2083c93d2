"""One goal of the back travel (one landmark), whatever the mode (:func:`make_goal`); between
goals :class:`CommandHold` (paper modes) or :class:`HandoverBridge` (closed_loop)."""
from .back_travel import MODES, DistanceController, TimeController

#: s closed_loop's follower goes on driving between two goals (:class:`HandoverBridge`).
HANDOVER_FOLLOW = 1.0


class SectionGoal(object):
    """Goal ``index`` of a closed-loop return driven by the shared ``follower``; ``since``: its
    ``travelled`` when the goal before ended (None: from this goal's start)."""

    def __init__(self, follower, index, since=None):
        self.follower = follower
        self.index = index
        self.done = self.failed = False
        self.reason, self.code = '', 0
        self._travelled_before = 0.0
        self._since = since

    travelled = property(lambda self: self.follower.travelled - self._travelled_before)

    def start(self, odom_state):
        if not self.follower.started:
            self.follower.start(odom_state, section=self.index)
            self._since = None
        self._travelled_before = self.follower.travelled if self._since is None else self._since
        self.done = self.follower.section_finished(self.index)

    def hold(self, seconds):
        """Nothing to do: the follower re-tracks from the pose."""

    def resumed(self, seconds):
        self.follower.pause_ended()

    def step(self, odom_state):
        command = self.follower.step(odom_state)
        self.failed, self.reason, self.code = self.follower.failed, self.follower.reason, self.follower.code
        self.done = not self.failed and self.follower.section_finished(self.index)
        return (0.0, 0.0) if self.done or self.failed else command


class CommandHold(object):
    """Between two goals the last published command holds for ``handover_timeout`` s, then
    zero; only a goal that publishes renews it (docs/back_travel.md, "Roles")."""

    def __init__(self, handover_timeout):
        if not handover_timeout > 0:
            raise ValueError('handover_timeout must be > 0 s, got %r' % (handover_timeout,))
        self.handover_timeout = float(handover_timeout)
        self.last = None            # when a goal last published a command (s), None: never

    def published(self, now):
        self.last = now

    def remaining(self, now):
        """s the last command still holds at ``now`` (0 also if the clock moved back)."""
        if self.last is None or now < self.last:
            return 0.0
        return max(0.0, self.last + self.handover_timeout - now)

    def expired(self, now):
        return self.remaining(now) <= 0.0


class HandoverBridge(object):
    """closed_loop between two goals: the ``follower`` drives on for ``timeout`` s, then zero."""

    def __init__(self, follower, timeout, now):
        if not timeout > 0:
            raise ValueError('handover_follow must be > 0 s, got %r' % (timeout,))
        self.follower, self.deadline = follower, now + float(timeout)

    def expired(self, now):
        return now >= self.deadline

    ended = property(lambda self: self.follower.done or self.follower.failed)

    def step(self, odom_state):
        return (0.0, 0.0) if self.ended else self.follower.step(odom_state)


def bridges(mode, follower, done, goals, follow=HANDOVER_FOLLOW):
    """True if a :class:`HandoverBridge` drives once ``done`` of ``goals`` are done."""
    return mode == 'closed_loop' and follow > 0 and follower is not None and follower.started and \
        0 < done < goals and not (follower.done or follower.failed)


def make_goal(mode, landmark, params=None, follower=None, index=None, since=None):
    """The goal for ``landmark`` in ``mode``; closed_loop needs the ``follower`` and ``index``."""
    if mode == 'closed_loop':
        if follower is None or index is None:
            raise ValueError('a closed_loop goal needs the return route follower and its index')
        return SectionGoal(follower, index, since)
    if mode == 'time':
        return TimeController(landmark, params)
    if mode == 'distance':
        return DistanceController(landmark, params)
    raise ValueError('unknown back-travel mode %r (expected one of %s)' % (mode, ', '.join(MODES)))

"""One goal of the back travel (one landmark), whatever the control mode.

:func:`make_goal` gives the paper's per-landmark controllers and closed_loop's shared
route follower one interface: ``start``, ``step`` (until ``done``/``failed``, ``reason``),
``travelled``, ``hold`` and ``resumed`` (a pause ended). Between goals the paper's modes
hold the last command (:class:`CommandHold`); closed_loop drives on (:class:`HandoverBridge`).
"""
from .back_travel import make_controller

#: s closed_loop's follower goes on driving between two goals (:class:`HandoverBridge`):
#: longer than nearly every action round trip at rtf 5 under load (docs/evaluation.md, issue 29).
HANDOVER_FOLLOW = 1.0


class SectionGoal(object):
    """Goal ``index`` (return order) of a closed-loop return driven by ``follower``
    (shared by the goals; started at the first goal it drives, at its section).
    ``since``: the follower's ``travelled`` when the goal before ended (what a
    :class:`HandoverBridge` drove in between counts to this goal), None: from its start."""

    def __init__(self, follower, index, since=None):
        self.follower = follower
        self.index = index
        self.done = self.failed = False
        self.reason, self.code = '', 0
        self._travelled_before = 0.0
        self._since = since

    @property
    def travelled(self):
        return self.follower.travelled - self._travelled_before

    def start(self, odom_state):
        if not self.follower.started:
            self.follower.start(odom_state, section=self.index)
            self._since = None
        self._travelled_before = self.follower.travelled if self._since is None else self._since
        self.done = self.follower.section_finished(self.index)

    def hold(self, seconds):
        """Nothing to do: the follower re-tracks from the pose, its progress watch skips
        gaps longer than max_step_gap."""

    def resumed(self, seconds):
        """A pause (takeover, contact) of ``seconds`` ended: what moved the robot meanwhile
        is not the follower's distance; it re-tracks from the pose (or fails, off the route)."""
        self.follower.pause_ended()

    def step(self, odom_state):
        command = self.follower.step(odom_state)
        self.failed, self.reason, self.code = self.follower.failed, self.follower.reason, self.follower.code
        self.done = not self.failed and self.follower.section_finished(self.index)
        return (0.0, 0.0) if self.done or self.failed else command


class ControllerGoal(object):
    """A paper-mode goal: its own core/back_travel controller."""

    def __init__(self, controller):
        self.controller = controller

    done = property(lambda self: self.controller.done)
    failed = property(lambda self: self.controller.failed)
    code = property(lambda self: self.controller.code)
    travelled = property(lambda self: self.controller.travelled)

    @property
    def reason(self):
        if not self.controller.failed:
            return ''
        if self.controller.reason:
            return self.controller.reason
        return 'time allowance %.1f s exceeded after %.3f m of %.3f m' % (
            self.controller.allowance, self.controller.travelled, self.controller.landmark.d)

    def start(self, odom_state):
        self.controller.start(odom_state)

    def hold(self, seconds):
        """The controller's clock skips the ``seconds`` held (time: T is driving time)."""
        if self.controller.started is not None:
            self.controller.started += seconds

    def resumed(self, seconds):
        """A pause (takeover, contact) of ``seconds`` ended: held time, and a replay that
        fails if the robot was moved meanwhile."""
        self.hold(seconds)
        self.controller.pause_ended()

    def step(self, odom_state):
        return self.controller.step(odom_state)


class CommandHold(object):
    """The output between two goals: the last command a goal published holds (the
    next goal follows at once: no stop-and-go between landmarks), but only for
    ``handover_timeout`` s after it was published; then zero.

    Only a goal that publishes renews the hold (:meth:`published`). A goal that
    ends as it starts (its section already done: the landmarks of a loop the
    route cut, a run of stationary ones) publishes nothing, so a run of them
    cannot keep the robot driving on the command of a goal that has ended: on
    ROS each goal costs an action round trip, and at a corner that command was
    the approach speed the follower had just stopped commanding."""

    def __init__(self, handover_timeout):
        if not handover_timeout > 0:
            raise ValueError('handover_timeout must be > 0 s, got %r' % (handover_timeout,))
        self.handover_timeout = float(handover_timeout)
        self.last = None            # when a goal last published a command (s), None: never

    def published(self, now):
        """A goal published a command at ``now`` (s)."""
        self.last = now

    def remaining(self, now):
        """s the last command still holds at ``now`` (0: zero velocity is due; also when
        ``now`` is before the command: the clock moved back, how long it held is unknown)."""
        if self.last is None or now < self.last:
            return 0.0
        return max(0.0, self.last + self.handover_timeout - now)

    def expired(self, now):
        """True once the last command no longer holds at ``now``."""
        return self.remaining(now) <= 0.0


class HandoverBridge(object):
    """closed_loop, from a goal's end to the next goal's start: the return's shared
    ``follower`` goes on driving the route (the command stays continuous, as the
    follower would give it without the hand-over), for at most ``timeout`` s from
    ``now``; then (:meth:`expired`) the output is zero. It never starts after the
    route's last goal, nor once the follower has finished or failed (:meth:`ended`)."""

    def __init__(self, follower, timeout, now):
        if not timeout > 0:
            raise ValueError('handover_follow must be > 0 s, got %r' % (timeout,))
        self.follower = follower
        self.started, self.deadline = now, now + float(timeout)

    def expired(self, now):
        """True once the bridge has driven its ``timeout``."""
        return now >= self.deadline

    @property
    def ended(self):
        """True once the follower has finished or failed (its command is zero)."""
        return self.follower.done or self.follower.failed

    def step(self, odom_state):
        """The follower's (v, w) for this cycle ((0, 0) once :attr:`ended`)."""
        return (0.0, 0.0) if self.ended else self.follower.step(odom_state)


def bridges(mode, follower, done, goals, follow=HANDOVER_FOLLOW):
    """True if a :class:`HandoverBridge` drives once ``done`` of the return's ``goals``
    are done: closed_loop, ``follow`` > 0 s, between two goals, the follower started
    and still driving."""
    return mode == 'closed_loop' and follow > 0 and follower is not None and follower.started and \
        0 < done < goals and not (follower.done or follower.failed)


def make_goal(mode, landmark, params=None, follower=None, index=None, since=None):
    """The goal for ``landmark`` in control ``mode``; closed_loop needs the
    return's ``follower`` and the goal's ``index`` (return order); ``since``:
    :class:`SectionGoal`'s."""
    if mode == 'closed_loop':
        if follower is None or index is None:
            raise ValueError('a closed_loop goal needs the return route follower and its index')
        return SectionGoal(follower, index, since)
    return ControllerGoal(make_controller(mode, landmark, params))

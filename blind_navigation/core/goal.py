"""One goal of the back travel (one landmark), whatever the control mode.

The action server drives one landmark per goal (the paper's protocol). In the
paper's modes each goal has its own controller (core/back_travel.make_controller:
``time``, ``distance``); in ``closed_loop`` the goals of a return share one
core/route_follower.RouteFollower over the whole route, and a goal ends when the
follower has finished the goal's section of the route. :func:`make_goal` gives
both the same interface::

    goal = make_goal(mode, landmark, params, follower, index)
    goal.start(odom_state)
    v, w = goal.step(odom_state)     # until goal.done or goal.failed (goal.reason says why)
    goal.travelled                   # m of odometry driven during this goal
    goal.hold(seconds)               # the robot was held (paused) that long: not driving time
    goal.resumed(seconds)            # a takeover or contact of that long ended (the robot may have moved)

The back_travel server and the simulation harness both drive goals through it,
and both hold the output between two goals with :class:`CommandHold`.
"""
from .back_travel import make_controller


class SectionGoal(object):
    """Goal ``index`` (return order) of a closed-loop return driven by ``follower``
    (shared by the goals; started at the first goal it drives, at its section)."""

    def __init__(self, follower, index):
        self.follower = follower
        self.index = index
        self.done = self.failed = False
        self.reason = ''
        self._travelled_before = 0.0

    @property
    def travelled(self):
        return self.follower.travelled - self._travelled_before

    def start(self, odom_state):
        if not self.follower.started:
            self.follower.start(odom_state, section=self.index)
        self._travelled_before = self.follower.travelled
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
        self.failed, self.reason = self.follower.failed, self.follower.reason
        self.done = not self.failed and self.follower.section_finished(self.index)
        return (0.0, 0.0) if self.done or self.failed else command


class ControllerGoal(object):
    """A paper-mode goal: its own core/back_travel controller."""

    def __init__(self, controller):
        self.controller = controller

    done = property(lambda self: self.controller.done)
    failed = property(lambda self: self.controller.failed)
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


def make_goal(mode, landmark, params=None, follower=None, index=None):
    """The goal for ``landmark`` in control ``mode``; closed_loop needs the
    return's ``follower`` and the goal's ``index`` (return order)."""
    if mode == 'closed_loop':
        if follower is None or index is None:
            raise ValueError('a closed_loop goal needs the return route follower and its index')
        return SectionGoal(follower, index)
    return ControllerGoal(make_controller(mode, landmark, params))

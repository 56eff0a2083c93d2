"""What the mission drives, stepped once per control cycle: the pi turn (TurnDrive), the
return's goals (ReturnDrive; RemoteReturn: sent to a remote driver), the pauses of a drive
(core/pause). Used by core/mission.
"""
from . import mission_state, outcome
from .allowance import ABORT, DRIVE, HOLD
from .drive import DriveCycle
from .goal import CommandHold, HandoverBridge, bridges, make_goal
from .mission_limits import rotation_timeout, with_defaults
from .pause import CONTACT_DEFAULTS, PAUSE, TAKEOVER_DEFAULTS, Contacts, PauseLog, Takeover
from .rotation import Rotation, turn_problem

ZERO = (0.0, 0.0)
GOAL, HANDOVER, FINAL, DONE, FAILED = 'goal', 'hand-over', 'final hold', 'done', 'failed'


class PiTurn(object):
    """A pi turn from ``odom`` on ``feed(cycle)`` (:class:`ReturnDrive`): failed past
    core/mission_limits.rotation_timeout on ``clock`` (since the loss); checked by turn_problem."""

    def __init__(self, params, feed, odom, config, clock):
        self.feed, self.clock, self.tolerance = feed, clock, config.turn_tolerance
        self.timeout = rotation_timeout(params, config)
        self.start_yaw = self.yaw = odom.yaw
        self.phase, self.reason, self.code = 'turn', '', outcome.NONE

    def where(self):
        return 'the pi turn'

    def _fail(self, code, reason):
        self.phase, self.reason, self.code = FAILED, reason, code
        return ZERO


class TurnDrive(PiTurn):
    """The pi turn driven here (core/rotation.Rotation): done once the robot really turned."""

    def __init__(self, params, feed, odom, config, clock):
        self.rotation = Rotation(params)
        PiTurn.__init__(self, params, feed, odom, config, clock)
        self.cycle = DriveCycle(params, hold=self.rotation.hold)
        self.rotation.start(odom)

    def resumed(self, seconds):
        self.rotation.hold(seconds)
        self.clock.resumed(seconds)

    def step(self, now, inputs):
        if self.clock.elapsed(now) > self.timeout:
            return self._fail(outcome.TIMEOUT, 'no finished pi turn within %.0f s of vision loss '
                              '(rotation_timeout: the standstill\'s timeout + rotation_margin + '
                              'vision_back_grace); not travelling back' % self.timeout)
        decision, odom, message = self.feed(self.cycle)
        if decision == ABORT:
            return self._fail(outcome.ODOMETRY, 'the pi rotation: %s; not travelling back' % message)
        command = self.rotation.step(odom) if decision == DRIVE else ZERO
        self.yaw = odom.yaw if odom is not None else self.yaw
        if self.rotation.failed:
            return self._fail(outcome.TIMEOUT, 'the pi rotation failed (not done within its '
                              'time_allowance of %.0f s); not travelling back'
                              % self.rotation.time_allowance)
        if not self.rotation.done:
            return command
        problem = turn_problem(self.start_yaw, self.yaw, self.tolerance)
        if problem:
            return self._fail(outcome.TURN, 'the pi turn: %s' % problem)
        self.phase = DONE
        return ZERO


class ReturnDrive(object):
    """The goals ``[(label, landmark)]`` (return order) driven one after another in ``mode``
    (``follower``: closed_loop's RouteFollower); ``feed(cycle)`` -> (decision, odom, message);
    ``latest()``: the odometry a goal starts from; ``watch``: core/mission_limits.ReturnWatch."""

    def __init__(self, goals, mode, params, follower, config, feed, latest, watch):
        self.goals, self.mode, self.params, self.follower = goals, mode, params, follower
        self.watch, self.driven = watch, 0.0    # m the goals done drove
        self.feed, self.latest, self.hold = feed, latest, CommandHold(config.handover_timeout)
        self.timeout, self.follow = config.handover_timeout, config.handover_follow
        self.await_goals = config.await_goals
        self.command = ZERO         # in force: the last a goal (or the bridge) published
        self.index = 0              # the goal driven, or next
        self.goal = self.bridge = self.since = self.final_at = self.cycle = None
        self.phase = HANDOVER     # the first goal starts at the first step
        self.reason, self.code = '', outcome.NONE

    @property
    def remaining(self):
        """The landmarks not driven yet (the current goal's included)."""
        return [landmark for _, landmark in self.goals[self.index:]]

    def where(self):
        return 'goal %d' % (self.index + 1)

    def travelled(self):
        """m the current goal has driven (0 between goals)."""
        return self.goal.travelled if self.goal is not None and self.phase == GOAL else 0.0

    def step(self, now, inputs):
        """The command for this cycle (``inputs.next_goal``: the next goal, with ``await_goals``)."""
        next_goal = inputs.next_goal
        while True:
            if self.phase == HANDOVER:
                if self.await_goals and not next_goal and self.goal is not None:
                    return self._hand_over(now)
                next_goal, self.phase = False, GOAL
                self.goal = make_goal(self.mode, self.goals[self.index][1], self.params, self.follower,
                                      self.index, self.since)
                self.goal.start(self.latest())
                self.cycle = DriveCycle(self.params, hold=self.goal.hold)
            if self.phase == FINAL:
                if now - self.final_at < self.timeout - 1e-9:
                    return self.command
                self.phase = DONE
            if self.phase in (DONE, FAILED):
                return ZERO
            if self.goal.done:
                self._goal_done(now)
                continue
            problem = self.watch.problem(now, self.driven + self.goal.travelled)
            decision, odom, message = self.feed(self.cycle)
            if problem or decision == ABORT:     # a limit, or the odometry grace gave up
                return self._fail(*problem) if problem else self._fail(outcome.ODOMETRY, message)
            if decision == HOLD:
                self.command = ZERO
                return ZERO
            command = self.goal.step(odom)
            if self.goal.failed:
                return self._fail(self.goal.code, self.goal.reason)
            if not self.goal.done:
                self.command = command
                self.hold.published(now)
                return command
            self._goal_done(now)

    def resumed(self, seconds):
        """A pause of ``seconds`` ended (the robot may have moved)."""
        self.watch.resumed(seconds)
        if self.phase == GOAL:
            self.goal.resumed(seconds)
        elif self.bridge is not None:
            self.follower.pause_ended()

    def _fail(self, code, reason):
        self.phase, self.reason, self.code = FAILED, 'goal %d: %s' % (self.index + 1, reason), code
        return ZERO

    def _goal_done(self, now):
        self.index += 1
        self.driven += self.goal.travelled
        if self.index == len(self.goals):
            self.phase, self.final_at = FINAL, now
            return
        self.bridge = HandoverBridge(self.follower, self.follow, now) if bridges(
            self.mode, self.follower, self.index, len(self.goals), self.follow) else None
        self.cycle = DriveCycle(self.params)     # the bridge's
        self.since = self.follower.travelled if self.follower is not None and self.follower.started \
            else None
        self.phase = HANDOVER

    def _hand_over(self, now):
        """Between goals: the bridge drives on (stale odometry: zero), else the last command holds."""
        if self.bridge is not None:
            decision, odom, _ = self.feed(self.cycle)
            expired = self.bridge.expired(now) or self.bridge.ended or decision == ABORT
            self.command = self.bridge.step(odom) if decision == DRIVE and not expired else ZERO
            if decision == DRIVE and not expired:
                self.hold.published(now)
            self.bridge = None if expired else self.bridge
        elif self.hold.expired(now):
            self.command = ZERO
        return self.command


class RemoteReturn(object):
    """The return's ``goals`` driven elsewhere (a BackTravel action goal each): :attr:`send` is the
    goal to send this cycle, ``inputs.goal_result`` its core/drive.Outcome; ``watch``: ReturnWatch."""

    def __init__(self, goals, watch):
        self.goals, self.index, self.phase, self.reason, self.code = goals, 0, GOAL, '', outcome.NONE
        self.send, self._sent, self.watch = None, None, watch

    remaining, where, _fail = ReturnDrive.remaining, ReturnDrive.where, ReturnDrive._fail
    travelled = staticmethod(lambda: 0.0)

    def resumed(self, seconds):
        """Pauses are the remote driver's."""

    def take(self):
        """The goal to send now, once: None after (a mission that ends sends nothing more)."""
        goal, self.send = self.send, None
        return goal

    def step(self, now, inputs):
        result = inputs.goal_result
        self.watch.update(now, bool(inputs.operator or inputs.bumper))    # paused: not counted
        problem = self.watch.problem(now, 0.0) if self._sent is not None else None
        if problem and self.phase != DONE:
            self._fail(problem.code, problem.reason)
            return None
        if result is not None and self._sent == self.index:
            if not result.ok:
                self._fail(result.cause, result.reason)
                return None
            self.index += 1
        if self.index == len(self.goals):
            self.phase = DONE
        self.send = None if self.phase == DONE or self._sent == self.index else \
            (self.index, self.goals[self.index][1])
        if self.send is not None:
            self.watch.goal(self.send[1], now)
        self._sent = self.index
        return None


class Pauses(object):
    """The pauses of one drive (module docstring); ``params``: core/pause's names
    (defaults where missing); ``contacts``: a bumper press pauses (else it stops the drive)."""

    def __init__(self, params, contacts=True):
        params = with_defaults(params, dict(CONTACT_DEFAULTS, **TAKEOVER_DEFAULTS))
        self.contacts = Contacts(params) if contacts else None
        self.takeover, self.log = Takeover(params), PauseLog(params.contact_wait)
        self.paused_at = self.taken = None

    def cycle(self, now, pressed, operator, position, driven):
        """This cycle of ``driven`` (told ``resumed(seconds)`` when a pause ended): False (drive on),
        None (a takeover: publish nothing), ZERO (a contact) or the core/outcome.Ending (a contact
        too many or too long, a bumper without contacts)."""
        if not (pressed or operator or self.paused_at is not None or self.log.takeovers or
                self.log.contacts):
            return False        # nothing ever paused this drive: nothing to track
        if operator:
            self.takeover.command(operator, now)
        taken = self.takeover.active(now)
        self.log.update(now, taken, pressed, position)
        if taken:
            self.taken, pause = taken, 'taken'
        elif self.contacts is None:
            pause = 'bumper pressed' if pressed else None
        else:
            pause = self.contacts.decide(bool(pressed), now, sensors=pressed if isinstance(pressed, tuple) else ())
            if pause and pause != PAUSE:
                pause = '%s: %s' % (', '.join(self.contacts.sensors) or 'bumper', pause)
        if pause in ('taken', PAUSE):
            self.paused_at = now if self.paused_at is None else self.paused_at
            return None if pause == 'taken' else ZERO
        if pause:
            return outcome.Ending(outcome.CONTACTS, '%s: safety stop: %s' % (driven.where(), pause))
        if self.paused_at is not None:      # a pause ended
            seconds, taken = now - self.paused_at, self.taken
            self.paused_at = self.taken = None
            if taken and self.takeover.policy == 'abort':
                return outcome.Ending(outcome.TAKEOVER, '%s (on_takeover abort)' % taken)
            driven.resumed(seconds)
        return False

    def describe(self, now):
        return self.log.describe(now)

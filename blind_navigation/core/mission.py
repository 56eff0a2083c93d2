"""The mission as one sequential object: record -> standstill -> pi turn -> return -> terminal,
stepped by its owner's one loop (``step(now, inputs) -> Step``). No threads, no clock, no
transport: the ROS layer and sim/harness.py both drive it (docs/DESIGN.md, "The default layer:
one mission, one loop").
"""
import collections
import types

from . import mission_state as state, outcome
from .allowance import ABORT, DRIVE, HOLD
from .back_travel import BACK_TRAVEL_DEFAULTS
from .docking import DOCK, Docking
from .drive import Outcome
from .final_approach import APPROACH, SETTLE, ReturnEnding
from .goal import HANDOVER_FOLLOW
from .heading_correction import CorrectedOdometry, correct_landmarks
from .mission_drive import DONE, FAILED, ZERO, Pauses, RemoteReturn, ReturnDrive, TurnDrive
from .mission_limits import LIMIT_DEFAULTS, PausedClock, ReturnWatch
from .mission_record import MissionRecording, Standstill
from .return_plan import (frame_lost, nothing_to_retrace, plan_return, recording_problem,
                          return_warning, still_loss)
from .route_follower import RouteFollower

#: The mission's settings beyond the controllers' params (each overridable by keyword).
MISSION_DEFAULTS = {
    'straight_period': 2.0, 'curved_period': 1.0, 'deadband': 0.01,   # the sampling (core/segment)
    'event_sampling': False,        # extra landmarks at motion events (core/motion_events)
    'heading_correction': True,     # the standstill and the gyro correction at the loss
    'standstill': None,             # its params (core/gyro_bias), None: the defaults
    'scale_prior': None,            # the calibrated gyro scale (core/gyro_calibration)
    'mode': 'closed_loop', 'prune_loops': False,    # the return's control mode, pruning
    'handover_timeout': 0.1, 'handover_follow': HANDOVER_FOLLOW,    # core/goal's hold, bridge
    'await_goals': False,           # the owner sends each next goal (Inputs.next_goal)
    'remote_goals': False,          # the goals are driven elsewhere (Step.goal, Inputs.goal_result)
    'remote': None,                 # recording, standstill, turn elsewhere: core/mission_remote.Remote
    'on_vision_back': 'home',       # core/mission_state.ON_VISION_BACK
    'settle_time': 2.0,             # s the home check waits for the robot to stop
    'turn_tolerance': 0.3,          # rad a finished pi turn may differ from pi
    'vision_back_grace': LIMIT_DEFAULTS['vision_back_grace'],   # s the turn waits for vision back
    'limits': None,                 # the allowances' params (core/mission_limits), None: params'
    'battery_low': 0.0,             # V: Inputs.battery below it starts the return (core/battery); 0: off
    'dock_at_home': False, 'dock_timeout': None,    # core/docking: dock once home (None: its default)
}


Inputs = collections.namedtuple(
    'Inputs', 'odom visual vision_lost vision_back bumper operator tripped reset time_back next_goal '
    'goal_result battery docking', defaults=(None, (), False, False, False, None, None, None, None, False,
                                             None, None, None))
Inputs.__doc__ = ('What the owner observed since the last step: ``odom`` (raw OdomState or None), '
                  '``visual`` [(stamp, yaw)], ``bumper`` (True or the bumpers\' names), ``operator``, '
                  '``tripped``, ``reset``, ``time_back``: who or why, ``goal_result``: the core/drive.Outcome '
                  'of the goal (or turn) sent, ``battery`` (V), ``docking``: a core/docking.DockingResult.')


Step = collections.namedtuple('Step', 'command phase state stored goal dock')
Step.__doc__ = ('``command``: (v, w) to publish or None (nothing); ``phase``; ``state``; ``stored``: the '
                'landmarks stored this step; ``goal``: (index, landmark) to send now (remote_goals), else '
                'None; ``dock``: send the docking goal now (core/docking).')

RECORDING, STANDSTILL, TURN, TURNED, ENDED = 'recording', 'standstill', 'turn', 'turned', 'ended'
#: Why a mission starts ``returning`` (the default layer's reason too).
RESUMED = 'resume after a restart'


class Mission(object):
    """One mission. ``params``: the controllers' params; ``store``: core/store's ``append``,
    ``load``, ``loss``, ``note_gap``; ``settings``: :data:`MISSION_DEFAULTS`; ``kept``: a
    core/resume.KeptReturn to resume (``returning``)."""

    def __init__(self, params, store, kept=None, **settings):
        self.params, self.store = params, store
        self.config = types.SimpleNamespace(**dict(MISSION_DEFAULTS, **_known(settings)))
        self.machine = state.MissionState()
        self.transitions, self.now = [], None   # (now, old, new, reason) of every change
        self._new(store)
        if kept is not None:
            self.kept, self.phase, self.loaded, self.landmarks, self.anchor = (
                kept, TURNED, kept.loaded, kept.landmarks, kept.anchor)
            self.correction, self.reference = kept.correction, kept.reference
            self.corrector = None if kept.correction is None else CorrectedOdometry.started(
                kept.correction, kept.reference, snapshot=kept.frame)
        self._move(None, state.IDLE if kept is None else state.RETURNING, RESUMED if kept else '')

    def _new(self, store):
        self.store, self.phase = store, RECORDING
        self.recording = (self.config.remote.recording if self.config.remote else MissionRecording)(store, self.config)
        self.raw = self.last = self.corrector = self.correction = None
        self.loaded = self.landmarks = self.anchor = self.route = self.pruning = self.planned = None
        self.drive, self.ending, self.kept, self.warning = None, None, None, ''  # warning: the return's
        self.pauses, self.requests, self.halt, self.vision_loss = Pauses(self.params), [], False, False

    state = property(lambda self: self.machine.state, doc='The mission state (core/mission_state).')
    reason = property(lambda self: self.machine.reason, doc='Why it is in that state.')

    def go_home(self):
        """Start the return (as a vision loss) while recording; the refusal or None."""
        refusal = state.go_home_refusal(self.state)
        if refusal is None:
            self.requests.append('go_home')
        return refusal

    def cancel(self, reason=None, code=outcome.CANCELLED):
        """Abort for ``reason``, core/outcome ``code`` (a fault names both); the refusal or None."""
        refusal = state.cancel_refusal(self.state)
        if refusal is None:
            self._end(state.ABORTED, code, reason or state.CANCELLED)
        return refusal

    def new_mission(self, store):
        """A terminal mission -> ``idle``, recording into ``store``; the refusal or None."""
        refusal = state.new_mission_refusal(self.state)
        if refusal is None:
            self._move(self.state, state.IDLE)
            self._new(store)
        return refusal

    def configure_return(self, **settings):
        """Before the return starts: its settings, ``landmarks`` (recording order), ``planned`` (plan_return's)."""
        if self.phase != TURNED:
            raise RuntimeError('the return is configured before it starts, not in %s' % self.phase)
        self.landmarks, self.planned = settings.pop('landmarks', self.landmarks), settings.pop('planned', self.planned)
        self.config.__dict__.update(_known(settings))

    def step(self, now, inputs=Inputs()):
        """One cycle at ``now`` (s, the owner's clock) with ``inputs``: the :class:`Step`."""
        stored, ended, self.now = [], self.phase == ENDED, now
        if inputs.odom is not None:
            self.raw = inputs.odom
            self.last = self.odom()
        where = {STANDSTILL: 'the pi turn', TURN: 'the pi turn', DOCK: 'the docking'}.get(self.phase, 'the return')
        lost = inputs.time_back or inputs.reset
        if lost and self.state in (state.ROTATING, state.RETURNING):
            self._end(state.ABORTED, outcome.CLOCK if inputs.time_back else outcome.ODOMETRY,
                      frame_lost('%s during %s' % (lost, where)))
        elif inputs.tripped and self.phase not in (RECORDING, ENDED):   # a safety stop after the recording
            self._end(state.ABORTED, outcome.SAFETY_EVENT, '%s: safety stop: %s' % (where, inputs.tripped))
        command = self._step(now, inputs, stored)
        self.halt = self.halt and ended     # the step that ended the mission returned zero
        return Step(command, self.phase, self.state, stored, self.drive.take() if isinstance(self.drive, RemoteReturn)
                    else None, self.phase == DOCK and self.drive.requested())

    def _step(self, now, inputs, stored):
        if self.phase == ENDED:
            halt, self.halt = self.halt, False
            return ZERO if halt else None
        if self.phase == RECORDING:
            return self._record(now, inputs, stored)
        if self.phase == STANDSTILL:
            return self._standstill(now, inputs)
        if self.phase in (SETTLE, APPROACH):
            return self._ending(now, inputs)
        if self.phase == DOCK:      # the dock drive drives: nothing published until it ends
            ended = self.drive.step(now, inputs)
            return ended and self._end(*ended)
        if self.phase == TURNED and self.last is not None:     # resumed: once odometry came
            _plan(self)
        return self._drive(now, inputs) if self.drive is not None else None

    def odom(self):
        """The latest odometry as the return sees it (corrected once the correction is known)."""
        if self.corrector is not None and self.raw is not None and (
                self.corrector.state is None or self.corrector.state.stamp != self.raw.stamp):
            self.corrector.update(self.raw)
        return self.raw if self.corrector is None or self.raw is None else self.corrector.state

    def _feed(self, cycle):
        """(decision, odometry stamped now, message) of a behaviour's core/drive.DriveCycle."""
        decision, message = cycle.decide(self.now, self.last.stamp)
        if isinstance(decision, Outcome):
            return ABORT, None, decision.reason
        return (HOLD, None, message) if decision == HOLD else \
            (DRIVE, self.last._replace(stamp=self.now), message)

    def _end(self, new, code, reason):
        if self.drive is not None or self.state == state.RETURNING:
            pauses = self.pauses.describe(self.now or 0.0)
            reason = '%s; %s' % (reason, pauses) if pauses and pauses not in reason else reason
        old = self.state
        if self.machine.abort(reason, code)[0] if new == state.ABORTED else \
                self.machine.transition(old, new, reason, code):
            self.transitions.append((self.now, old, new, reason))
        self.phase, self.halt = ENDED, True
        return ZERO

    def _move(self, old, new, reason=''):
        if self.machine.transition(old, new, reason):
            self.transitions.append((self.now, old, new, reason))

    def _record(self, now, inputs, stored):
        rec = self.recording
        if inputs.reset:
            rec.reset(self.raw, inputs.reset)
        if inputs.odom is not None and not rec.started:
            rec.begin(inputs.odom)
        elif inputs.odom is not None:
            rec.feed(inputs.odom, inputs.visual)
            stored.extend(rec.step(inputs.odom, now))
        if stored or rec.reported:
            self._move(state.IDLE, state.RECORDING)
        low = self.recording.battery.update(now, inputs.battery)
        why = 'vision lost' if inputs.vision_lost else low or (
            'return requested (go_home)' if 'go_home' in self.requests else None)
        if why and self.state == state.RECORDING:
            self.requests = []
            return self._lose(now, stored, why, inputs.vision_lost)
        return None

    def _lose(self, now, stored, reason, vision):
        """Vision lost (or go_home): the recording's last landmark, then the standstill (or the end)."""
        raw, rec = self.raw, self.recording
        stored.extend(rec.end(raw, now))
        if rec.lost:
            return self._end(state.ABORTED, outcome.ODOMETRY, '%s, but %s' % (reason, frame_lost(rec.lost)))
        nothing = nothing_to_retrace(rec.distance, rec.start, (raw.x, raw.y),
                                     BACK_TRAVEL_DEFAULTS['finish_tolerance'])
        if nothing:
            return self._end(state.HOME, outcome.NOTHING_TO_RETRACE, '%s: %s' % (reason, nothing))
        loss = self.store.loss()
        problem = recording_problem(self.store.load(), loss) if loss.count and not still_loss(loss) else None
        if problem:
            return self._end(state.ABORTED, problem.code, '%s, but %s' % (reason, problem.reason))
        self._move(state.RECORDING, state.ROTATING, reason)
        self.phase, self.vision_loss, self.reference, self.lost_at, self.turn_clock = \
            STANDSTILL, vision, raw, now, PausedClock(now)      # the turn's timeout, takeovers out
        self.standstill = (self.config.remote.standstill if self.config.remote else Standstill)(
            self.recording.fit, raw, self.config.standstill, self.config.scale_prior)
        return self._standstill(now, Inputs())

    def _standstill(self, now, inputs):
        if inputs.vision_back and self.vision_loss:
            self._move(state.ROTATING, state.RECORDING, 'brief vision loss, vision back %.1f s after '
                       'the loss: the mission goes on' % (now - self.lost_at))
            self.phase = RECORDING
            self.recording.resume()
            return None
        self.turn_clock.update(now, inputs.operator)
        correction = self.standstill.correction(now, inputs.odom)
        grace = self.config.vision_back_grace if self.vision_loss and self.standstill.fit is None else 0.0
        return None if correction is None or now < self.lost_at + grace - 1e-9 else \
            self._commit(now, correction)

    def _commit(self, now, correction):
        """The turn begins: the recording ends, the correction is fixed, the pi turn starts."""
        self.loaded, loss = self.store.load(), self.store.loss()
        problem, self.warning = recording_problem(self.loaded, loss), return_warning(self.loaded, loss)
        if problem:
            return self._end(state.ABORTED, problem.code, 'before the pi turn: %s' % problem.reason)
        self.correction, self.corrector = correction, CorrectedOdometry(correction)
        self.corrector.update(self.reference)
        self.landmarks = correct_landmarks(self.loaded.landmarks, correction)
        self.anchor = (self.reference.x, self.reference.y)
        self.pauses = Pauses(self.params, contacts=False)
        self.last = self.odom()
        self.phase, self.drive = TURN, (self.config.remote.turn if self.config.remote else TurnDrive)(
            self.params, self._feed, self.last, self.config, self.turn_clock)
        return self._drive(now, Inputs())

    def _paused(self, now, inputs):
        """Vision back's zero, a pause's command ('taken': nothing, a contact: zero), an end, or
        False (drive on); remote goals pause where they are driven."""
        if self._vision_back(inputs):
            return ZERO
        if isinstance(self.drive, RemoteReturn):
            return False
        position = lambda: None if self.last is None else [self.last.x, self.last.y]  # noqa: E731
        paused = self.pauses.cycle(now, inputs.bumper, inputs.operator, position, self.ending or self.drive)
        return self._end(state.ABORTED, *paused) if isinstance(paused, outcome.Ending) else paused

    def _drive(self, now, inputs):
        """A cycle of the turn or the return (:attr:`drive`): vision back, pauses, its command."""
        paused = self._paused(now, inputs)
        if paused is not False:
            return paused
        command = self.drive.step(now, inputs)
        if self.drive.phase == FAILED:
            return self._end(state.ABORTED, self.drive.code, self.drive.reason)
        if self.drive.phase != DONE:
            self.phase = self.drive.phase
            return command
        if self.phase == TURN:
            self._move(state.ROTATING, state.RETURNING)
            self.phase, self.drive = TURNED, None
            return ZERO
        self.phase, self.ending = SETTLE, ReturnEnding(now, self.params, self.config, self.route, len(
            self.drive.goals), self.warning, self._feed, self.odom, not self.config.remote_goals)
        return self._ending(now, inputs) or ZERO

    def _ending(self, now, inputs):
        """After the last goal: core/final_approach.ReturnEnding's command, or its verdict's end."""
        paused = self._paused(now, inputs) if self.phase == APPROACH else False
        if paused is not False:
            return paused
        command, verdict = self.ending.step(now)
        self.phase = self.ending.phase
        if verdict is None:
            return command
        if verdict[0] != state.HOME or not self.config.dock_at_home:
            return self._end(*verdict)
        self._move(state.RETURNING, state.DOCKING, verdict[2])
        self.phase, self.drive = DOCK, Docking(verdict[2], now, self.config.dock_timeout)
        return ZERO

    def _vision_back(self, inputs):
        """Vision back in the turn or the return: ``recovered`` with on_vision_back stop."""
        if not (inputs.vision_back and self.vision_loss and self.config.on_vision_back == 'stop'
                and self.state in (state.ROTATING, state.RETURNING)):
            return False
        if self.state != state.RETURNING or self.drive is None:
            where, left = 'the pi turn', 'the whole path'
        else:
            left = sum(abs(landmark.d) for landmark in self.drive.remaining) - self.drive.travelled()
            where, left = 'the return', '%.2f m' % max(left, 0.0)
        return self._end(state.RECOVERED, outcome.VISION_BACK, 'vision back during %s: stopped '
                         '(on_vision_back stop), %s left to home' % (where, left)) is ZERO


def _plan(m):
    """Mission ``m``'s return: its route (closed_loop; pruned with prune_loops; or kept) and its goals."""
    c, follower, kept = m.config, None, m.kept
    labels = getattr(m.loaded, 'labels', [])
    if len(labels) != len(m.landmarks):
        labels = [str(number + 1) for number in range(len(m.landmarks))]
    goals = list(zip(labels, m.landmarks))[::-1]    # (label, landmark), the last recorded first
    if c.mode == 'closed_loop':
        m.route, m.pruning = (kept.route, None) if kept else m.planned or plan_return(
            m.landmarks, m.anchor, m.params, c.prune_loops, m.correction)
        follower = None if c.remote_goals else RouteFollower(m.route, m.params)
    m.pauses, done = Pauses(m.params), kept.done if kept else 0
    watch = ReturnWatch(m.landmarks, [landmark for _, landmark in goals[done:]], c.limits or m.params, m.now)
    m.drive = RemoteReturn(goals, watch) if c.remote_goals else ReturnDrive(
        goals, c.mode, m.params, follower, c, m._feed, m.odom, watch)
    m.drive.index, m.drive.driven = done, kept.travelled if kept else 0.0


def _known(settings):
    """``settings``, checked to be :data:`MISSION_DEFAULTS`' names."""
    unknown = ', '.join(sorted(set(settings) - set(MISSION_DEFAULTS)))
    if unknown:
        raise ValueError('Mission: unknown settings %s' % unknown)
    return settings

"""Plain-Python mission harness for Monte-Carlo evaluation of the whole layer.

One run = what the ROS graph does, over the same core objects, at a fixed
control step: a scripted operator (sim/mission.py) drives a SimulatedKobuki
(sim/kobuki.py; with the ``base`` setting ``mujoco`` the physics base,
sim/mujoco_kobuki.py) while the two-rate SamplingSchedule and the PathRecorder
take landmarks from its odometry; the mission ends, the robot is left to stop,
vision is lost (a final landmark covers the partial cycle, the return route is
anchored at the odometry position), core/rotation.py turns by pi, and the
landmarks are driven back in reverse order.
Between goals, as back_travel_server does, closed_loop's follower goes on driving
(core/goal.HandoverBridge, at most ``handover_follow``) and the paper's modes hold
the last command (core/goal.CommandHold: at most ``handover_timeout`` after a goal
last published); ``handover_latency`` is the time a hand-over takes, 0 by default, an
action round trip on ROS; after the last goal the last command is dropped after
``handover_timeout``. The landmark store is
written for real (core/landmark_writer.LandmarkWriter) to measure its size, and landmarks
are read back from it, so the return uses the stored (rounded) numbers.

With ``heading_correction`` (blind_navigation.launch's ``heading_correction``,
on by default), the fake TurtleBot's visual odometry (sim/visual_odometry.py,
fake_vision's drift and 30 Hz rate and seed + 1) runs while recording; at
vision loss the robot stands still until the bias is known well enough for
this mission (``heading_budget``, at most ``standstill_time`` s), and
core/heading_correction.py estimates the gyro bias from both and takes the
scale from ``gyro_calibration`` (what calibrate_gyro.launch measured; make one
with :func:`simulate_gyro_calibration`, on another seed: another power-up of the
same robot). The pi turn and the return then run on the corrected odometry with
the landmarks expressed in the same frame, as the heading_correction node and
back_travel_client do.

Goals are driven as back_travel_server drives them (core/goal.make_goal), one
per landmark in return order: ``closed_loop`` builds the whole route at once
(core/route.build_route) and the goals are the sections of one
core/route_follower.RouteFollower; ``time`` and ``distance`` run one controller
per landmark. With ``prune_loops`` the closed-loop route is pruned first
(core/pruning.prune_route, with the mission's heading correction), as
back_travel_client prunes it.

Missions are mission files (sim/mission.py) or command series
(sim/command_series.py: seeded random paths from sim/random_paths.py,
replayed real trajectories from config/paths).

The physical floor (``floor`` setting): on a copy of the same robot after the
same recording, standstill and pi turn (same seed, same state), a follower
tracks the recorded 50 Hz odometry poses backwards (every odometry state that
moved 1 cm, turned 0.05 rad or reversed since the last one kept, as a landmark:
:func:`dense_landmarks`; in the same heading-corrected frame, the same route
builder and follower): ``dense_error`` is its true final error, ``floor_error`` the true
error it would have had had its odometry ended exactly on the start (the
residual odometry offset at its end mapped out through the odometry-to-truth
transform there): what tracking the recorded odometry perfectly leaves, which
no landmark scheme can beat. :func:`run_modes` records once per configuration
and runs every mode's return (and the floor) from copies of that state.

The result holds the ground-truth final position error (the paper's "position
error": distance between the start and where the robot stopped), odometry's
own view of it, the recorded distance, samples, bytes, both true paths, and
the floor.
"""
import copy
import math
import os
import tempfile
from collections import namedtuple
from types import SimpleNamespace

from ..core.allowance import ABORT, DRIVE, HOLD, OdomGrace
from ..core.route_follower import RouteFollower
from ..core.goal import HANDOVER_FOLLOW, CommandHold, HandoverBridge, bridges, make_goal
from ..core.geometry import distance, wrap_angle
from ..core.landmark import Landmark
from ..core.motion_events import EventSampler
from ..core.pruning import prune_route
from ..core.route import build_route
from ..core.gyro_bias import (STANDSTILL_DEFAULTS, StandstillBias, standstill_complete,
                              standstill_timeout)
from ..core.gyro_calibration import CalibrationError, SpinCalibration
from ..core.gyro_fit import GyroVisualFit
from ..core.heading_correction import (CorrectedOdometry, correct_landmarks, estimate_correction,
                                       no_correction, visual_bias)
from ..core.recorder import OdometryHistory, PathRecorder
from ..core.rotation import Rotation
from ..core.segment import SamplingSchedule
from ..core.landmark_writer import LandmarkWriter
from ..core.store import load_landmarks
from .kobuki import load_profile, make_profile
from .mujoco_kobuki import make_base
from .mission import load_mission
from .visual_odometry import VO_DRIFT_DEFAULTS, VO_RATE, DriftingOdometry

#: Harness settings (keyword arguments of :func:`run_mission`).
SIMULATION_DEFAULTS = {
    'control_dt': 0.02,        # s, control and sampling step (the nodes run at 50 Hz)
    'straight_period': 2.0,    # s, sampling period on straight segments (paper: 0.5 Hz)
    'curved_period': 1.0,      # s, on curves (paper: 1 Hz)
    'deadband': 0.01,          # rad, classifier dead-band (core/segment.py)
    'settle_time': 2.0,        # s between the mission's end and the vision loss
    'start_delay': 0.0,        # s the robot stands recording before the operator's first command
                               # (ROS: the layer records from its start, the operator starts later)
    'handover_timeout': 0.1,   # s the last command holds after the last goal (and at most
                               # this long after a goal last published, between goals)
    'handover_latency': 0.0,   # s from one goal's end to the next goal's start (ROS: the
                               # action's round trip, tens of ms of wall time x the rtf)
    'handover_follow': HANDOVER_FOLLOW,  # closed_loop: s the follower goes on driving between
                               # goals (core/goal.HandoverBridge; 0: it holds, as the paper's modes)
    'stop_time': 2.0,          # s left for the robot to stop at the end
    'heading_correction': True,  # blind_navigation.launch's heading_correction (default on)
    'standstill_time': STANDSTILL_DEFAULTS['standstill_time'],  # s, longest standstill after
                               # vision loss measuring the gyro bias (with heading_correction)
    'heading_budget': STANDSTILL_DEFAULTS['heading_budget'],  # rad: it ends earlier once the
                               # bias std x the recording's duration is within this
    'standstill_min': STANDSTILL_DEFAULTS['standstill_min'],  # s, but not before this
    'gyro_calibration': None,  # the gyro's calibrated scale (core/gyro_calibration.GyroCalibration)
    'floor': True,             # also run the physical floor (module docstring)
    'event_sampling': False,   # an extra landmark at each motion event (core/motion_events.py:
                               # a proposal; off = the paper's sampling)
    'odometry_gaps': (),       # ((start, length), ...) s after the pi turn starts: odometry stops
                               # arriving (held as the nodes hold: core/allowance.OdomGrace)
    'base': 'kinematic',       # the robot: kinematic (sim/kobuki.py) or mujoco (sim/mujoco_kobuki.py)
    'world': 'tile',           # the mujoco base's floor (config/worlds name or path)
    'payload': (0.0, 0.0, 0.0),  # the mujoco base's payload: kg, x, y m of its centre of mass
    'prune_loops': False,      # closed_loop: cut loops and doubled-back stretches from the route
                               # (core/pruning.py, its params from ``params``), as the client's
                               # prune_loops does
}
#: Settings that change only the return: modes differing in them share a recording (run_modes).
RETURN_SETTINGS = ('prune_loops',)

MissionResult = namedtuple('MissionResult', [
    'mission', 'profile', 'mode', 'seed', 'status', 'reason',
    'distance', 'samples', 'bytes', 'position_error', 'odom_error',
    'forward_path', 'return_path', 'duration', 'landmarks', 'heading_correction',
    'floor_error', 'dense_error', 'late', 'route_length', 'return_length', 'return_time',
    'pruning', 'forward_times'])
MissionResult.__doc__ = ('One simulated mission: status home|aborted, distance (m, sum of d), '
                         'samples, bytes (landmark file), position_error (m, ground truth), '
                         'odom_error (m, as odometry sees it), true paths [(x, y)], duration (s), '
                         'landmarks (as stored and read back), heading_correction '
                         '(core/heading_correction.GyroCorrection), floor_error and dense_error '
                         '(m, the physical floor, module docstring; None without the floor), '
                         'late (closed_loop goals over their nominal time), route_length (m, the '
                         'closed_loop route driven, pruned or not; None otherwise), return_length (m, '
                         'the true path from the return\'s start) and return_time (s, from the return\'s '
                         'start to its last goal), pruning (core/pruning.PruneResult with prune_loops, '
                         'else None), forward_times (s: the sim time of each forward_path point).')


class _Run(object):
    """The robot, its clock and the recorded true path of one mission; while
    ``fit`` is set, visual odometry and odometry feed it; once
    ``corrector`` is set, :meth:`odom` is the corrected odometry."""

    def __init__(self, profile, seed, dt, correct_heading=False, base=('kinematic', 'tile', (0.0, 0.0, 0.0))):
        self.base = make_base(base[0], profile, seed=seed, world=base[1], payload=base[2])
        self.dt = dt
        self.path = []
        self.path_times = []          # sim time of each point of ``path``
        self.fit = GyroVisualFit() if correct_heading else None
        self.vision = DriftingOdometry(seed + 1, **VO_DRIFT_DEFAULTS)
        self.next_frame = 0.0
        self.corrector = None
        self.odometry_log = None      # a list: every odometry state is appended

    def advance(self, command=None):
        if command is not None:
            self.base.command(*command)
        self.base.step(self.dt)
        if self.odometry_log is not None:
            self.odometry_log.append(self.base.odom)
        pose = self.base.true_pose
        if not self.path or distance(self.path[-1][0], self.path[-1][1], pose.x, pose.y) > 0.005:
            self.path.append((pose.x, pose.y))
            self.path_times.append(self.base.t)
        if self.fit is not None:
            self.fit.add_odometry(self.base.odom.stamp, self.base.odom.yaw)
            while self.next_frame <= self.base.t + 1e-9:   # as fake_vision clocks its frames
                self.fit.add_visual(self.next_frame, self.vision.update(pose).yaw)
                self.next_frame += 1.0 / VO_RATE

    def lose_vision(self, standstill, scale_prior):
        """Vision fails: with heading correction the robot stands still measuring the gyro
        bias until core/gyro_bias.standstill_complete (``standstill``:
        its params), then the correction is estimated; the corrected frame starts
        where vision was lost."""
        if self.fit is None:
            self.corrector = CorrectedOdometry(no_correction('heading correction off'))
            return self.corrector.correction
        fit, self.fit = self.fit, None
        reference = self.base.odom
        measurement = StandstillBias(standstill)
        visual, _ = visual_bias(fit, scale_prior)
        recording_time = fit.recording_time(reference.stamp)
        timeout = reference.stamp + standstill_timeout(standstill)
        while not standstill_complete(visual, measurement, recording_time, standstill) \
                and self.base.t < timeout:
            self.advance()
            measurement.add_odometry(self.base.odom)
        correction = estimate_correction(fit, measurement.estimate(), scale_prior)
        self.corrector = CorrectedOdometry(correction)
        self.corrector.update(reference)
        return correction

    def odom(self):
        """Odometry as the return sees it (corrected once vision is lost)."""
        raw = self.base.odom
        if self.corrector is None:
            return raw
        if self.corrector.state is None or self.corrector.state.stamp != raw.stamp:
            self.corrector.update(raw)
        return self.corrector.state


def _record(run, mission, settings, store_path):
    """Drive the mission while sampling; returns the loaded store and the anchor."""
    base, dt = run.base, run.dt
    schedule = SamplingSchedule(settings['straight_period'], settings['curved_period'],
                                settings['deadband'])
    recorder = PathRecorder()
    recorder.start(base.odom)
    period = schedule.update(base.odom.yaw)
    next_tick, last_tick = period, 0.0
    operator_every = max(1, int(round(1.0 / (mission.rate * dt))))
    operator = mission.make_operator()
    if operator is not None:
        operator.start(base.true_pose)
    settle_steps = int(round(settings['settle_time'] / dt))
    events = EventSampler() if settings['event_sampling'] else None
    latency = events.latency if events else 0.0
    history = OdometryHistory(max(2.0, 2.0 * latency))
    if events:
        events.start(0.0)
    with LandmarkWriter(store_path, fsync=False, metadata={'mission': mission.name}) as writer:

        def take(state, period):
            writer.append(recorder.take(state, state.yaw, period))
            return state.stamp

        def take_events(before, last_tick):
            """Landmarks at the motion events stamped before ``before`` (time order);
            returns the stamp of the last landmark."""
            for state, event_period in events.before(before, history.at) if events else ():
                last_tick = take(state, event_period)
            return last_tick

        k, finished_at = -int(round(settings['start_delay'] / dt)), None     # k: operator steps
        while finished_at is None or k < finished_at + settle_steps:
            command = None
            if finished_at is None and k >= 0 and k % operator_every == 0:
                command = (mission.command_at(k * dt) if operator is None else operator.command(k * dt))
                if command is None:
                    finished_at, command = k, (0.0, 0.0)
            run.advance(command)
            k += 1
            if operator is not None and k > 0:
                operator.observe(k * dt, base.true_pose)
            if events is not None:
                history.append(base.odom)
                events.odometry(base.odom)
            if base.t >= next_tick + latency - 1e-9:
                # with event sampling the tick is taken latency s late, from the odometry at its
                # stamp (as the saver reads it), so events dated back before it come first
                state = history.at(next_tick + 1e-9) if latency else base.odom
                take_events(state.stamp, last_tick)
                last_tick = take(state, events.tick(state.stamp, period) if events else period)
                period = schedule.update(state.yaw)
                next_tick = state.stamp + period
        last_tick = take_events(base.t + 1.0, last_tick)
        if base.t - last_tick > 1e-9:   # vision lost: the final partial cycle
            writer.append(recorder.take(base.odom, base.odom.yaw, base.t - last_tick))
    return load_landmarks(store_path), (base.odom.x, base.odom.y)


class _OdometryFeed(object):
    """The odometry the nodes would act on, with the gaps of the ``odometry_gaps``
    setting (odometry stops arriving): within ``odom_timeout`` of the last state
    the control loop still steps on it (stamped now, as LatestOdom.fresh gives
    it), then holds at zero (core/allowance.OdomGrace) until odometry returns,
    or aborts after ``odom_grace``."""

    def __init__(self, run, gaps, params):
        start = run.base.t
        self.run = run
        self.gaps = [(start + begin, start + begin + length) for begin, length in gaps]
        self.grace = OdomGrace(params)
        self.last = None

    def state(self):
        """(decision, OdomState or None, message): DRIVE with the state to step on,
        HOLD (command zero) or ABORT."""
        now = self.run.base.t
        if not any(begin <= now < end for begin, end in self.gaps):
            self.last = self.run.odom()
        decision, message = self.grace.check(now, self.last.stamp)
        return decision, self.last._replace(stamp=now) if decision == DRIVE else None, message


def _turn(run, params, settings):
    rotation, feed = Rotation(params), _OdometryFeed(run, settings['odometry_gaps'], params)
    rotation.start(run.odom())
    while True:
        decision, odom, _ = feed.state()
        if decision == ABORT:
            run.base.command(0.0, 0.0)
            return False
        command = rotation.step(odom) if decision == DRIVE else (0.0, 0.0)
        if rotation.done or rotation.failed:
            run.base.command(0.0, 0.0)
            return rotation.done
        run.advance(command)


def _return(run, landmarks, anchor, mode, params, settings, correction=None, prune=False):
    """Drive ``landmarks`` back, one goal per landmark in return order, through
    core/goal.make_goal as back_travel_server does (closed_loop: the sections of
    one RouteFollower over the whole route, pruned with ``prune`` as the client
    prunes it: core/pruning.prune_route with the heading ``correction``). Returns
    (why it aborted or '', the follower or None, the PruneResult or None)."""
    follower = pruning = None
    if mode == 'closed_loop':
        route = build_route(landmarks, anchor, params)
        if prune:
            pruning = prune_route(route, landmarks, correction, params)
            route = pruning.route
        follower = RouteFollower(route, params)
    command, feed = (0.0, 0.0), _OdometryFeed(run, settings['odometry_gaps'], params)
    hold, since = CommandHold(settings['handover_timeout']), None
    for index, landmark in enumerate(reversed(landmarks)):
        if index:
            bridge = HandoverBridge(follower, settings['handover_follow'], run.base.t) \
                if bridges(mode, follower, index, len(landmarks), settings['handover_follow']) else None
            since = follower.travelled if follower is not None and follower.started else None
            command = _hand_over_between(run, command, hold, settings['handover_latency'], bridge, feed)
        goal = make_goal(mode, landmark, params, follower, index, since)
        goal.start(run.odom())
        while not goal.done:
            decision, odom, message = feed.state()
            if decision == ABORT:
                run.base.command(0.0, 0.0)
                return 'goal %d: %s' % (index + 1, message), follower, pruning
            if decision == HOLD:
                command = (0.0, 0.0)
                run.advance(command)
                continue
            v, w = goal.step(odom)
            if goal.failed:
                run.base.command(0.0, 0.0)
                return 'goal %d: %s' % (index + 1, goal.reason), follower, pruning
            if goal.done:
                break
            command = (v, w)
            hold.published(run.base.t)
            run.advance(command)
    _hand_over(run, command, settings)
    return '', follower, pruning


def _hand_over_between(run, command, hold, latency, bridge=None, feed=None):
    """``latency`` s from one goal's end to the next one's start: the ``bridge``
    (core/goal.HandoverBridge, closed_loop) steps the follower on ``feed``'s odometry
    until it expires, then zero; without one the last ``command`` holds while ``hold``
    (core/goal.CommandHold) lets it, then zero. Returns the command in force at the
    next goal's start."""
    for _ in range(int(round(latency / run.dt))):
        if bridge is not None:
            decision, odom, _ = feed.state()     # stale odometry holds at zero, as the drive loop
            expired = bridge.expired(run.base.t) or bridge.ended or decision == ABORT
            command = bridge.step(odom) if decision == DRIVE and not expired else (0.0, 0.0)
            if decision == DRIVE and not expired:
                hold.published(run.base.t)
            bridge = None if expired else bridge
        elif hold.expired(run.base.t):
            command = (0.0, 0.0)
        run.advance(command)
    return command


def _hand_over(run, command, settings):
    """After the last goal the server holds the last command ``handover_timeout`` s, then stops."""
    for _ in range(int(round(settings['handover_timeout'] / run.dt))):
        run.advance(command)
    run.base.command(0.0, 0.0)


def dense_landmarks(odometry, spacing=0.01, turn=0.05):
    """The recorded odometry as landmarks (v, w, d, T, psi) at every state that moved
    ``spacing`` m or turned ``turn`` rad since the previous one kept, or reversed
    (the route merges closer points anyway): the recorded path at the odometry's
    own rate."""
    landmarks, kept = [], odometry[0] if odometry else None
    for index, state in enumerate(odometry[1:], 1):
        step = distance(kept.x, kept.y, state.x, state.y)
        if step >= spacing or abs(wrap_angle(state.yaw - kept.yaw)) >= turn or state.v * kept.v < 0 \
                or index == len(odometry) - 1:
            if state.stamp > kept.stamp:
                landmarks.append(Landmark(state.v, state.w, step, state.stamp - kept.stamp,
                                          wrap_angle(state.yaw)))
                kept = state
    return landmarks


def _floor(run, odometry, anchor, correction, params, settings):
    """(floor_error, dense_error) of the physical floor (module docstring) on ``run``."""
    dense = correct_landmarks(dense_landmarks(odometry), correction)
    reason, follower, _ = _return(run, dense, anchor, 'closed_loop', params, settings)
    route = follower.route
    _stop(run, settings)
    truth, odom = run.base.true_pose, run.odom()
    start = run.path_start
    dense_error = distance(start[0], start[1], truth.x, truth.y)
    if reason:
        return float('nan'), dense_error
    goal_x, goal_y = route.x[-1], route.y[-1]
    turn = truth.yaw - odom.yaw
    dx, dy = goal_x - odom.x, goal_y - odom.y
    x = truth.x + math.cos(turn) * dx - math.sin(turn) * dy
    y = truth.y + math.sin(turn) * dx + math.cos(turn) * dy
    return distance(start[0], start[1], x, y), dense_error


def _stop(run, settings):
    for _ in range(int(round(settings['stop_time'] / run.dt))):
        run.advance()


def simulate_gyro_calibration(profile='paper', seed=0, params=None, control_dt=0.02, base='kinematic',
                              world='tile'):
    """Run core/gyro_calibration.SpinCalibration on a fake Kobuki (``seed``: its
    gyro bias; visual odometry from ``seed`` + 1, as in a mission; ``base``,
    ``world``: as run_mission's) and return the :class:`GyroCalibration`
    (CalibrationError if not determined)."""
    profile = load_profile(profile) if isinstance(profile, str) else make_profile(profile)
    run = _Run(profile, seed, control_dt, base=(base, world, (0.0, 0.0, 0.0)))
    spin = SpinCalibration(params)
    run.fit = spin.fit
    while not spin.done:
        command = spin.step(run.base.odom)
        if spin.failed:
            raise CalibrationError(spin.failed)
        run.advance(command)
    return spin.result()


def _settings(settings):
    unknown = set(settings) - set(SIMULATION_DEFAULTS)
    if unknown:
        raise ValueError('run_mission: unknown settings %s' % ', '.join(sorted(unknown)))
    return dict(SIMULATION_DEFAULTS, **settings)


def default_params(settings, profile):
    """Controller params as the nodes run them on this robot: ``stop_lead`` is the
    handover timeout plus the base's velocity time constant."""
    return SimpleNamespace(straight_period=settings['straight_period'],
                           stop_lead=settings['handover_timeout'] + profile['motor_time_constant'])


class _Recorded(object):
    """One mission recorded, vision lost and turned by pi: the state every mode's
    return starts from (copied per mode by :func:`run_modes`)."""

    def __init__(self, mission, profile, seed, settings, store_dir):
        self.mission = load_mission(mission) if isinstance(mission, str) else mission
        self.profile_name = profile if isinstance(profile, str) else 'custom'
        self.profile = load_profile(profile) if isinstance(profile, str) else make_profile(profile)
        self.seed, self.settings = seed, settings
        run = self.run = _Run(self.profile, seed, settings['control_dt'], settings['heading_correction'],
                              (settings['base'], settings['world'], tuple(settings['payload'])))
        if settings['floor']:
            run.odometry_log = [run.base.odom]
        start = run.base.true_pose
        run.path_start = (start.x, start.y)
        with tempfile.TemporaryDirectory(dir=store_dir) as directory:
            store_path = os.path.join(directory, 'landmarks.yaml')
            self.loaded, self.anchor = _record(run, self.mission, settings, store_path)
            self.size = os.path.getsize(store_path)
        self.odometry, run.odometry_log = run.odometry_log, None
        self.forward_path, run.path = run.path, [run.path[-1]] if run.path else []
        self.forward_times, run.path_times = run.path_times, run.path_times[-1:]
        standstill = SimpleNamespace(**{name: settings[name] for name in STANDSTILL_DEFAULTS
                                        if name in settings})
        self.correction = run.lose_vision(standstill, settings['gyro_calibration'])
        self.landmarks = correct_landmarks(self.loaded.landmarks, self.correction)
        self.turned = None

    def turn(self, params):
        if self.turned is None:
            self.turned = _turn(self.run, params, self.settings)
        return self.turned

    def floor(self, params):
        """(floor_error, dense_error) on a copy of the turned robot."""
        if not self.settings['floor'] or not self.turned:
            return None, None
        return _floor(copy.deepcopy(self.run), self.odometry, self.anchor, self.correction,
                      params, self.settings)

    def finish(self, run, mode, params, floor, settings=None):
        """Drive ``mode``'s return on ``run`` (this state or a copy) with ``settings``
        (default: the recording's; they may differ in :data:`RETURN_SETTINGS`): the
        MissionResult."""
        settings = self.settings if settings is None else settings
        returned_from, started = len(run.path) - 1, run.base.t
        reason, follower, pruning = ('pi rotation failed', None, None) if not self.turned else \
            _return(run, self.landmarks, self.anchor, mode, params, settings, self.correction,
                    settings['prune_loops'])
        late = follower.late if follower is not None else []
        return_time = run.base.t - started
        _stop(run, settings)
        driven = run.path[max(0, returned_from):]
        end, odom = run.base.true_pose, run.base.odom
        start = run.path_start
        floor_error, dense_error = floor
        return MissionResult(
            self.mission.name, self.profile_name, mode, self.seed,
            'aborted' if reason else 'home', reason, self.loaded.total_distance,
            len(self.loaded.landmarks), self.size, distance(start[0], start[1], end.x, end.y),
            math.hypot(odom.x, odom.y), self.forward_path, run.path, run.base.t,
            self.loaded.landmarks, self.correction, floor_error, dense_error, late,
            follower.route.length if follower is not None else None,
            sum(distance(a[0], a[1], b[0], b[1]) for a, b in zip(driven, driven[1:])), return_time,
            pruning, self.forward_times)


def run_mission(mission, profile='ideal', mode='closed_loop', seed=0, params=None,
                store_dir=None, **settings):
    """Simulate one mission end to end; returns a :class:`MissionResult`.

    ``mission``/``profile``: names (config/missions, config/noise) or paths, or a
    sim/mission.Mission (e.g. a command series); ``params``: controller/rotation
    params (object with attributes; :func:`default_params` otherwise);
    ``settings``: any of :data:`SIMULATION_DEFAULTS`.
    """
    settings = _settings(settings)
    recorded = _Recorded(mission, profile, seed, settings, store_dir)
    params = params if params is not None else default_params(settings, recorded.profile)
    recorded.turn(params)
    floor = recorded.floor(params)
    return recorded.finish(recorded.run, mode, params, floor)


def run_modes(mission, profile='ideal', modes=('closed_loop',), seed=0, params=None,
              settings_of=None, store_dir=None, run_mode=None):
    """{mode: MissionResult}: like :func:`run_mission` for each of ``modes`` (same
    results), recording once per configuration. ``settings_of(mode)`` gives a
    mode's settings (default: none); modes whose settings differ at most in
    :data:`RETURN_SETTINGS` share the recording, the standstill, the pi turn and
    the floor (the floor is the unpruned route's). ``run_mode(mode)``, if
    given, is the control mode a mode label drives (a label can name a mode in
    another configuration)."""
    results, shared = {}, {}
    for mode in modes:
        settings = _settings(settings_of(mode) if settings_of else {})
        key = tuple(sorted((k, repr(v)) for k, v in settings.items() if k not in RETURN_SETTINGS))
        if key not in shared:
            recorded = _Recorded(mission, profile, seed, settings, store_dir)
            mode_params = params if params is not None else default_params(settings, recorded.profile)
            recorded.turn(mode_params)
            shared[key] = (recorded, mode_params, recorded.floor(mode_params))
        recorded, mode_params, floor = shared[key]
        results[mode] = recorded.finish(copy.deepcopy(recorded.run), run_mode(mode) if run_mode else mode,
                                        mode_params, floor, settings)
    return results

"""Plain-Python mission harness: core/mission.Mission, the object the ROS layer drives, on a
simulated Kobuki (sim/kobuki.py; sim/mujoco_kobuki.py with ``base`` mujoco) at a fixed control
step. A scripted operator (sim/mission.py) drives while the mission records; vision is lost
``settle_time`` s after; the mission's standstill, pi turn and return then drive the robot.
Scripted events (sim/mission_events.py) play bumps, takeovers, requests, vision and resets.
:func:`run_modes` records once and returns every mode from copies; the physical floor
(:func:`_floor`) drives the recorded odometry back. docs/DESIGN.md, docs/evaluation.md.
"""
import copy
import math
import os
import tempfile
from collections import namedtuple
from types import SimpleNamespace

from ..core import mission_state
from ..core.files import StorageError
from ..core.goal import HANDOVER_FOLLOW
from ..core.geometry import distance, wrap_angle
from ..core.gyro_bias import STANDSTILL_DEFAULTS
from ..core.gyro_calibration import CalibrationError, SpinCalibration
from ..core.heading_correction import correct_landmarks
from ..core.landmark import Landmark
from ..core.mission_files import LandmarkWriter
from ..core.docking import DOCK
from ..core.final_approach import APPROACH, SETTLE
from ..core.mission import RECORDING, STANDSTILL, TURN, TURNED, Inputs, Mission
from ..core.mission_drive import FAILED, FINAL, GOAL, HANDOVER
from ..core.odometry_reset import UNTRUSTED
from ..core.return_plan import write_loss
from ..core.store import load_landmarks
from .battery import SimBattery
from .dock import Dock, dock_from_spec
from .docking import dock_mission
from .kobuki import CommandLag, load_profile, make_profile
from .mujoco_kobuki import make_base
from .mission import load_mission
from .mission_events import ScriptedEvents
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
    'command_lag': 0.0,        # s the return's commands reach the base late (a loaded machine's
                               # late control cycles: its final stop overshoots)
    'turn_lag': 0.0,           # s the standstill's and pi turn's commands reach the base late
    'odometry_gaps': (),       # ((start, length), ...) s after the pi turn starts: odometry stops
                               # arriving (held as the nodes hold: core/allowance.OdomGrace)
    'base': 'kinematic',       # the robot: kinematic (sim/kobuki.py) or mujoco (sim/mujoco_kobuki.py)
    'world': 'tile',           # the mujoco base's floor (config/worlds name or path)
    'payload': (0.0, 0.0, 0.0),  # the mujoco base's payload: kg, x, y m of its centre of mass
    'on_vision_back': 'home',  # vision back in the turn or the return: home (go on) or stop
    'vision_back_grace': 0.0,  # s the turn waits for vision back without heading correction
                               # (paper.launch's; blind_navigation.launch's: 5)
    'limits': None,            # the return's and the turn's allowances (core/mission_limits
                               # names: the client's params), None: from ``params``
    'events': (),              # scripted events (sim/mission_events.Event tuples): bumper presses,
                               # an operator's takeover, cancel, go_home, vision lost/back
    'prune_loops': False,      # closed_loop: cut loops and doubled-back stretches from the route
                               # (core/pruning.py, its params from ``params``), as the client's
                               # prune_loops does
    'battery': None,           # the Kobuki battery: sim/battery.SimBattery's keyword arguments
                               # (volts, drain, motion, noise), read each step; None: no reading
    'battery_low': 0.0,        # V: the mission's battery_low (core/battery; 0: off)
    'dock': None,              # the Kobuki's dock: a sim/dock.Dock, or dock_from_spec's spec
                               # ('start': behind the start pose); None: none
    'dock_at_home': False,     # the mission docks once home (core/docking; sim/docking.dock_mission)
}
#: Settings the core/mission.Mission takes as they are.
_MISSION_SETTINGS = ('straight_period', 'curved_period', 'deadband', 'event_sampling',
                     'heading_correction', 'handover_timeout', 'handover_follow', 'on_vision_back',
                     'vision_back_grace', 'limits', 'battery_low', 'dock_at_home')
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
    ``vision_on``, the fake visual odometry's frames collect in ``frames`` (while
    ``fit`` is set, calibration: they feed it, with odometry)."""

    def __init__(self, profile, seed, dt, correct_heading=False, base=('kinematic', 'tile', (0.0, 0.0, 0.0))):
        self.base = make_base(base[0], profile, seed=seed, world=base[1], payload=base[2])
        self.dt = dt
        self.path = []
        self.path_times = []          # sim time of each point of ``path``
        self.fit = None
        self.vision_on = self.correct_heading = correct_heading
        self.frames = []
        self.vision = DriftingOdometry(seed + 1, **VO_DRIFT_DEFAULTS)
        self.next_frame = 0.0
        self.odometry_log = None      # a list: every odometry state is appended
        self.battery = None           # a sim/battery.SimBattery, drained as the robot moves
        self.dock = self.docking = None   # a sim/dock.Dock; the sim/docking.DockingResult of its docking
        self.lag = None               # a CommandLag: commands reach the base late

    def give(self, command):
        """``command`` (None: none) given now: to the base (through the lag, if any)."""
        if self.lag is not None:
            command = self.lag.delay(self.base.t, command)
        if command is not None:
            self.base.command(*command)

    def advance(self, command=None):
        self.give(command)
        self.base.step(self.dt)
        if self.battery is not None:
            self.battery.step(self.dt, *self.base.true_twist)
        if self.odometry_log is not None:
            self.odometry_log.append(self.base.odom)
        pose = self.base.true_pose
        if not self.path or distance(self.path[-1][0], self.path[-1][1], pose.x, pose.y) > 0.005:
            self.path.append((pose.x, pose.y))
            self.path_times.append(self.base.t)
        if self.fit is not None:
            self.fit.add_odometry(self.base.odom.stamp, self.base.odom.yaw)
        if self.fit is not None or self.vision_on:
            while self.next_frame <= self.base.t + 1e-9:   # as fake_vision clocks its frames
                yaw = self.vision.update(pose).yaw
                if self.fit is not None:
                    self.fit.add_visual(self.next_frame, yaw)
                else:
                    self.frames.append((self.next_frame, yaw))
                self.next_frame += 1.0 / VO_RATE


class _Store(object):
    """The mission's landmark store: written for real (core/mission_files), read back at the
    turn; a failed write is counted by the writer (lost) and kept in ``error``."""

    def __init__(self, path, name):
        self.path = path
        self.writer = LandmarkWriter(path, fsync=False, metadata={'mission': name})
        self.size, self.error = None, ''

    def __deepcopy__(self, memo):
        return self                   # closed once the turn begins; copies share it

    def append(self, landmark):
        try:
            self.writer.append(landmark)
        except StorageError as error:
            self.error = str(error)

    def loss(self):
        return write_loss(self.writer, self.error)

    def note_gap(self, reason):
        try:
            self.writer.note_gap(reason)
        except StorageError as error:
            self.error = str(error)

    def load(self):
        self.writer.close()
        self.size = os.path.getsize(self.path)
        return load_landmarks(self.path)


class _OdometryFeed(object):
    """Whether odometry arrives: not in the gaps of the ``odometry_gaps`` setting, s
    after the feed's start (the pi turn's, the return's)."""

    def __init__(self, start, gaps):
        self.gaps = [(start + begin, start + begin + length) for begin, length in gaps]

    def arrives(self, now):
        return not any(begin <= now < end for begin, end in self.gaps)


def _step(run, mission, events, feed=None, vision_lost=False, next_goal=False):
    """One mission step on the robot's state now: (Step, the scripted operator's
    command or None); the scripted ``events`` (sim/mission_events.py) come in."""
    now = run.base.t
    frames, run.frames = run.frames, []
    reset = events.fire('odometry_reset', now)
    if reset and hasattr(run.base, 'reset_odometry'):
        run.base.reset_odometry()       # the odometry restarts from the origin, as kobuki_node's
    odom = run.base.odom if feed is None or feed.arrives(now) else None
    battery = None if run.battery is None else run.battery.reading() / 10.0
    if not events.events:       # the bench's runs: no scripted event
        if vision_lost:
            run.vision_on = False
        return mission.step(now, Inputs(odom, frames, vision_lost, next_goal=next_goal,
                                        battery=battery)), None
    if events.fire('cancel', now):
        mission.cancel()
    if events.fire('go_home', now):
        mission.go_home()
    takeover = events.window('takeover', now)
    if getattr(run.base, 'motor_power', None) is not None:
        run.base.set_motor_power(events.window('motors_off', now) is None)
    vision_lost, vision_back = vision_lost or events.fire('vision_lost', now), events.fire('vision_back', now)
    run.vision_on = (run.vision_on or (vision_back and run.correct_heading)) and not vision_lost
    inputs = Inputs(odom=odom, visual=frames,
                    vision_lost=vision_lost, vision_back=vision_back,
                    bumper=events.window('bumper', now) is not None,
                    operator='scripted operator' if takeover else None, next_goal=next_goal,
                    tripped='cliff (scripted)' if events.fire('cliff', now) else None,
                    reset='%s (scripted)' % UNTRUSTED if reset else None,
                    time_back='the time moved back (scripted)' if events.fire('time_back', now) else None,
                    battery=battery)
    return mission.step(now, inputs), takeover and takeover.command


def _drive(run, mission, events, step, phases, feed=None, latency=0):
    """Advance the robot on the mission's commands (an operator's while one takes over)
    while its phase is one of ``phases``; the first Step out of them (its command set).
    ``latency``: steps from a goal's end until the next goal is sent (await_goals)."""
    handing, index = 0, None    # hand-over steps before the next goal, of the goal ``index``
    while step[0].phase in phases:
        command = step[1] or step[0].command
        run.advance(command)
        goal = getattr(mission.drive, 'index', None)
        handing = (handing + 1 if goal == index else 1) if step[0].phase == HANDOVER else 0
        index = goal
        step = _step(run, mission, events, feed, next_goal=handing >= latency)
    if step[0].command is not None:
        run.give(step[0].command)
    return step


def _record(run, sim_mission, settings, store_path):
    """The recording alone, as a mission records it (evaluation/forward.py): (the landmarks
    loaded from ``store_path``, the odometry (x, y) where vision was lost)."""
    run.events = ScriptedEvents()
    owner = Mission(SimpleNamespace(), _Store(store_path, sim_mission.name),
                    **dict({name: settings[name] for name in _MISSION_SETTINGS}, heading_correction=False))
    _record_mission(run, sim_mission, owner, settings, run.events)
    return owner.loaded, owner.anchor


def _record_mission(run, sim_mission, mission, settings, events):
    """Drive the mission while sampling until vision is lost: the mission's first Step after."""
    base, dt = run.base, run.dt
    _step(run, mission, events)                  # the first state: the recording starts
    operator_every = max(1, int(round(1.0 / (sim_mission.rate * dt))))
    operator = sim_mission.make_operator()
    if operator is not None:
        operator.start(base.true_pose)
    settle_steps = int(round(settings['settle_time'] / dt))
    k, finished_at = -int(round(settings['start_delay'] / dt)), None     # k: operator steps
    while True:
        command = None
        if finished_at is None and k >= 0 and k % operator_every == 0:
            command = (sim_mission.command_at(k * dt) if operator is None else operator.command(k * dt))
            if command is None:
                finished_at, command = k, (0.0, 0.0)
        run.advance(command)
        k += 1
        if operator is not None and k > 0:
            operator.observe(k * dt, base.true_pose)
        lost = finished_at is not None and k >= finished_at + settle_steps
        step = _step(run, mission, events, vision_lost=lost)
        if step[0].phase != RECORDING and (step[0].phase != STANDSTILL or finished_at is not None):
            return step
        if lost:
            raise RuntimeError('the mission ignored the vision loss (it is %s)' % mission.state)


def _turn(run, mission, step, settings):
    """The standstill's end and the pi turn: the Step after (phase ``turned`` if it went well)."""
    run.events.origin('turn', run.base.t)
    run.lag = CommandLag(settings['turn_lag']) if settings['turn_lag'] else None
    step = _drive(run, mission, run.events, step, (STANDSTILL,))
    feed = _OdometryFeed(run.base.t, settings['odometry_gaps'])
    return _drive(run, mission, run.events, step, (TURN,), feed)


def _return(run, mission, settings):
    """The return, as the mission drives it: its last Step (phase settle or ended)."""
    feed = _OdometryFeed(run.base.t, settings['odometry_gaps'])
    latency = int(round(settings['handover_latency'] / run.dt))
    mission.configure_return(await_goals=latency > 0)
    run.events.origin('return', run.base.t)
    run.lag = CommandLag(settings['command_lag']) if settings['command_lag'] else None
    step = _step(run, mission, run.events, feed)
    return _drive(run, mission, run.events, step, (GOAL, HANDOVER, FINAL), feed, latency)


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


def _floor(run, mission, odometry, settings):
    """(floor_error, dense_error): the physical floor on ``run``, ``mission`` (copies after the
    same recording, standstill and turn). A follower tracks the recorded 50 Hz odometry back
    (:func:`dense_landmarks`, in the corrected frame): dense_error is its true final error,
    floor_error the true error had its odometry ended exactly on the start (the residual offset
    mapped through the odometry-to-truth transform there), which no landmark scheme can beat."""
    mission.configure_return(landmarks=correct_landmarks(dense_landmarks(odometry), mission.correction),
                             mode='closed_loop', prune_loops=False)
    _return(run, mission, settings)
    route = mission.route
    _stop(run, mission, settings)
    truth, odom = run.base.true_pose, mission.odom()
    start = run.path_start
    dense_error = distance(start[0], start[1], truth.x, truth.y)
    if mission.drive.phase == FAILED:
        return float('nan'), dense_error
    goal_x, goal_y = route.x[-1], route.y[-1]
    turn = truth.yaw - odom.yaw
    dx, dy = goal_x - odom.x, goal_y - odom.y
    x = truth.x + math.cos(turn) * dx - math.sin(turn) * dy
    y = truth.y + math.sin(turn) * dx + math.cos(turn) * dy
    return distance(start[0], start[1], x, y), dense_error


def _stop(run, mission, settings):
    """``stop_time`` s for the robot to stop; the mission decides home meanwhile (or after), its
    commands played (its final approach: core/final_approach, the ``approach`` events' origin,
    an operator's takeover in it)."""
    steps, command = int(round(settings['stop_time'] / run.dt)), None
    while steps > 0 or mission.phase in (SETTLE, APPROACH):
        steps -= 1
        run.advance(command)
        approaching = mission.phase == APPROACH
        if approaching:
            run.events.origin('approach', run.base.t)
        step, taken = _step(run, mission, run.events)
        command = taken if taken and approaching else step.command


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

    def __init__(self, mission, profile, seed, settings, store_dir, params):
        self.mission = load_mission(mission) if isinstance(mission, str) else mission
        self.profile_name = profile if isinstance(profile, str) else 'custom'
        self.profile = load_profile(profile) if isinstance(profile, str) else make_profile(profile)
        self.seed, self.settings = seed, settings
        self.params = params if params is not None else default_params(settings, self.profile)
        run = self.run = _Run(self.profile, seed, settings['control_dt'], settings['heading_correction'],
                              (settings['base'], settings['world'], tuple(settings['payload'])))
        run.events = ScriptedEvents(settings['events'])
        run.battery = SimBattery(seed=seed, **settings['battery']) if settings['battery'] else None
        if settings['floor']:
            run.odometry_log = [run.base.odom]
        start = run.base.true_pose
        run.path_start = (start.x, start.y)
        dock = settings['dock']
        run.dock = dock if isinstance(dock, Dock) or dock is None else dock_from_spec(dock, start)
        standstill = SimpleNamespace(**{name: settings[name] for name in STANDSTILL_DEFAULTS
                                        if name in settings})
        with tempfile.TemporaryDirectory(dir=store_dir) as directory:
            store = _Store(os.path.join(directory, 'landmarks.yaml'), self.mission.name)
            self.owner = Mission(self.params, store, standstill=standstill,
                                 scale_prior=settings['gyro_calibration'],
                                 **{name: settings[name] for name in _MISSION_SETTINGS})
            step = _record_mission(run, self.mission, self.owner, settings, run.events)
            self.odometry, run.odometry_log = run.odometry_log, None
            self.forward_path, run.path = run.path, [run.path[-1]] if run.path else []
            self.forward_times, run.path_times = run.path_times, run.path_times[-1:]
            self.turned = _turn(run, self.owner, step, settings)[0].phase == TURNED
            store.writer.close()
            self.size = os.path.getsize(store.path)
        self.loaded = self.owner.loaded

    def floor(self):
        """(floor_error, dense_error) on a copy of the turned robot."""
        if not self.settings['floor'] or not self.turned:
            return None, None
        return _floor(*copy.deepcopy((self.run, self.owner)), odometry=self.odometry,
                      settings=self.settings)

    def finish(self, run, owner, mode, floor, settings=None):
        """Drive ``mode``'s return on ``run``, ``owner`` (this state or a copy) with ``settings``
        (default: the recording's; they may differ in :data:`RETURN_SETTINGS`): the
        MissionResult."""
        settings = self.settings if settings is None else settings
        returned_from, started = len(run.path) - 1, run.base.t
        if self.turned:
            owner.configure_return(mode=mode, prune_loops=settings['prune_loops'])
            _return(run, owner, settings)
        follower = getattr(owner.drive, 'follower', None)     # None: no return (a failed turn)
        return_time = run.base.t - started
        _stop(run, owner, settings)
        if owner.phase == DOCK:
            run.docking = dock_mission(run, owner, battery=16.0 if run.battery is None else
                                       run.battery.reading() / 10.0)
        driven = run.path[max(0, returned_from):]
        end, odom = run.base.true_pose, run.base.odom
        start = run.path_start
        floor_error, dense_error = floor
        loaded = self.loaded
        landmarks = loaded.landmarks if loaded is not None else owner.recording.landmarks
        home = owner.state == mission_state.HOME
        return MissionResult(
            self.mission.name, self.profile_name, mode, self.seed,
            'home' if home else owner.state, '' if home else owner.reason,
            loaded.total_distance if loaded is not None else owner.recording.distance,
            len(landmarks), self.size, distance(start[0], start[1], end.x, end.y),
            math.hypot(odom.x, odom.y), self.forward_path, run.path, run.base.t,
            landmarks, owner.correction, floor_error, dense_error,
            follower.late if follower is not None else [],
            follower.route.length if follower is not None else None,
            sum(distance(a[0], a[1], b[0], b[1]) for a, b in zip(driven, driven[1:])), return_time,
            owner.pruning, self.forward_times)


def run_mission(mission, profile='ideal', mode='closed_loop', seed=0, params=None,
                store_dir=None, **settings):
    """Simulate one mission end to end; returns a :class:`MissionResult`.

    ``mission``/``profile``: names (config/missions, config/noise) or paths, or a
    sim/mission.Mission (e.g. a command series); ``params``: controller/rotation
    params (object with attributes; :func:`default_params` otherwise);
    ``settings``: any of :data:`SIMULATION_DEFAULTS`.
    """
    return play(mission, profile, mode, seed, params, store_dir, **settings).result


Played = namedtuple('Played', 'result mission run')
Played.__doc__ = ('One simulated mission: its MissionResult, the core/mission.Mission that ran it '
                  '(state, reason, transitions) and the run (``base``: the simulated robot, ``path``, '
                  '``path_times``: its true return path).')


def play(mission, profile='ideal', mode='closed_loop', seed=0, params=None, store_dir=None, **settings):
    """:func:`run_mission`, returning a :class:`Played`."""
    settings = _settings(settings)
    recorded = _Recorded(mission, profile, seed, settings, store_dir, params)
    floor = recorded.floor()
    result = recorded.finish(recorded.run, recorded.owner, mode, floor)
    return Played(result, recorded.owner, recorded.run)


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
            recorded = _Recorded(mission, profile, seed, settings, store_dir, params)
            shared[key] = (recorded, recorded.floor())
        recorded, floor = shared[key]
        run, owner = copy.deepcopy((recorded.run, recorded.owner))
        results[mode] = recorded.finish(run, owner, run_mode(mode) if run_mode else mode, floor, settings)
    return results

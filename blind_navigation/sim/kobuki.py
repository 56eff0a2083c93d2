"""Simulated Kobuki base (TurtleBot2): kinematics, motors, encoders, gyro and error model.

Plain Python, no ROS: the fake TurtleBot node and the Monte-Carlo harness drive
the same object. What it reproduces (numbers from the Kobuki and kobuki_node):

* commands: ``command(v, w)`` clamps to 0.7 m/s and pi rad/s; kobuki_node drops a
  command 0.6 s after the last one, checked at 10 Hz; motor power off stops it.
* optional acceleration limiter on (v, w): +0.5/-0.6 m/s^2, +3.5/-4.2 rad/s^2.
* motors: each wheel's rim speed follows its target through a first-order lag
  (``motor_time_constant``, momentum), reaches only ``u (1 - speed_droop |u|)
  - friction_speed`` in steady state, and ripples (an Ornstein-Uhlenbeck process,
  larger at low speed, a share ``ripple_common`` of it common to both wheels) around it.
* ground truth: wheels of unequal diameter (UMBmark's ``E_d``), a scale error of
  the mean diameter (``E_s``) and slip proportional to speed turn wheel rotation
  into true motion, an exact arc over each physics step (with the ``ideal``
  profile the base is an exact unicycle: commands act at once, no error).
* sensors at 50 Hz: encoders quantized to 2578.33 ticks per revolution, a gyro
  with bias, scale error and white noise; odometry as kobuki_node computes it
  (encoder distance, gyro heading as ``use_imu_heading``, twist angular = gyro rate).

Every random draw comes from ``random.Random(seed)``: same seed, same run.
"""
import math
import random
from collections import deque

from ..core.geometry import OdomState, Pose2D, wrap_angle
from .config_dir import config_dir, load_named

WHEEL_RADIUS = 0.035          # m
WHEEL_SEPARATION = 0.230      # m
TICKS_PER_REV = 2578.33       # encoder ticks per wheel revolution
MAX_V = 0.7                   # m/s
MAX_W = math.pi               # rad/s
CMD_TIMEOUT = 0.6             # s, kobuki_node's cmd_vel_timeout
TIMEOUT_CHECK_PERIOD = 0.1    # s, the timeout is checked at 10 Hz
SENSOR_PERIOD = 0.02          # s, Kobuki core sensor stream at 50 Hz
#: kobuki_driver's acceleration limiter: m/s^2, rad/s^2 speeding up and slowing down.
ACCEL_LIMITS = {'v_up': 0.5, 'v_down': 0.6, 'w_up': 3.5, 'w_down': 4.2}
#: kobuki_node's odometry pose covariance (row-major 6x6 indices -> value)
ODOM_POSE_COVARIANCE = {0: 0.1, 7: 0.1, 14: 1e10, 21: 1e10, 28: 1e10, 35: 0.05}

#: Every profile parameter, its ideal value and meaning (units in the name's doc).
PROFILE_DEFAULTS = {
    'physics_dt': 0.01,            # s, integration step (divides 0.02 and 0.1)
    'acceleration_limiter': False, # kobuki_node's optional (v, w) rate limiter
    'motor_time_constant': 0.0,    # s, first-order wheel speed lag (momentum)
    'speed_droop': 0.0,            # 1/(m/s), steady state u (1 - droop |u|)
    'friction_speed': 0.0,         # m/s, rim speed lost to friction
    'ripple_std': 0.0,             # m/s, wheel speed ripple std at zero speed
    'ripple_knee': 0.1,            # m/s, ripple std = ripple_std / (1 + |u| / knee)
    'ripple_time': 0.3,            # s, ripple correlation time
    'ripple_common': 0.0,          # share of the ripple common to both wheels (0..1): moves
                                   # the robot's speed but not its heading
    'wheel_diameter_ratio': 1.0,   # UMBmark E_d = D_right / D_left
    'distance_scale': 1.0,         # UMBmark E_s = actual mean diameter / nominal
    'slip_per_speed': 0.0,         # fraction of rim speed lost per m/s of rim speed
    'gyro_bias_max': 0.0,          # rad/s, bias drawn uniform in +-max per run
    'gyro_scale_error': 0.0,       # fraction, measured rate = (1 + e) true rate
    'gyro_noise_std': 0.0,         # rad/s, white noise of each 50 Hz rate sample
}
PROFILE_DIR = config_dir('noise')


class CommandLag(object):
    """Commands given at ``t`` reach the base at ``t + seconds`` (the latest one due then): a
    loaded machine's late commands, in the harness and the fake alike."""

    def __init__(self, seconds):
        if not (math.isfinite(seconds) and seconds >= 0.0):
            raise ValueError('a command lag of %r s (give seconds >= 0)' % (seconds,))
        self.seconds, self.queue = seconds, deque()

    def delay(self, now, command):
        """``command`` (None: none) given at ``now``; the command due at ``now``, or None."""
        self.push(now, command)
        return self.due(now)

    def push(self, now, command):
        """``command`` given at ``now`` (due ``seconds`` later)."""
        if command is not None:
            self.queue.append((now + self.seconds, command))

    def due(self, now):
        """The latest command due at ``now`` (the others it overtook dropped), or None."""
        due = None
        while self.queue and self.queue[0][0] <= now + 1e-9:
            due = self.queue.popleft()[1]
        return due


def load_profile(name_or_path):
    """Noise profile dict: a name in config/noise/ (``ideal``, ``kobuki``, ``paper``) or a YAML path.

    Missing keys take the ideal value; unknown keys or wrong types raise ValueError
    naming the key and the file.
    """
    path, data = load_named(PROFILE_DIR, name_or_path, 'noise profile')
    return make_profile(data, where=path)


def make_profile(values, where='profile'):
    """Validated profile dict from ``values`` (overrides on top of the ideal defaults)."""
    if not isinstance(values, dict):
        raise ValueError('%s: a profile is a mapping, got %r' % (where, type(values).__name__))
    profile = dict(PROFILE_DEFAULTS)
    for key, value in values.items():
        if key == 'description':
            continue
        if key not in PROFILE_DEFAULTS:
            raise ValueError('%s: unknown noise parameter %r (known: %s)'
                             % (where, key, ', '.join(sorted(PROFILE_DEFAULTS))))
        default = PROFILE_DEFAULTS[key]
        if isinstance(default, bool):
            if not isinstance(value, bool):
                raise ValueError('%s: %s must be true or false, got %r' % (where, key, value))
        elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError('%s: %s must be a finite number, got %r' % (where, key, value))
        elif value < 0:
            raise ValueError('%s: %s must be >= 0, got %r' % (where, key, value))
        profile[key] = value
    for key in ('wheel_diameter_ratio', 'distance_scale', 'physics_dt', 'ripple_knee', 'ripple_time'):
        if profile[key] <= 0:
            raise ValueError('%s: %s must be > 0, got %r' % (where, key, profile[key]))
    if profile['ripple_common'] > 1.0:
        raise ValueError('%s: ripple_common must be in [0, 1], got %r' % (where, profile['ripple_common']))
    ratio = SENSOR_PERIOD / profile['physics_dt']
    if abs(ratio - round(ratio)) > 1e-6:
        raise ValueError('%s: physics_dt %r must divide %.2f s' % (where, profile['physics_dt'], SENSOR_PERIOD))
    return profile


def arc_motion(x, y, yaw, v, w, dt):
    """(x, y, yaw) after ``dt`` s of constant (v, w) from (x, y, yaw), exactly: a
    unicycle moves along the chord of its arc, ``2 sin(w dt / 2) / w`` times ``v``
    long, in the direction of the arc's middle (yaw not wrapped). The body of
    :class:`SimulatedKobuki` moves so between physics steps; paths planned as
    pieces of constant (v, w) are integrated with it too."""
    half = w * dt / 2.0
    chord = v * dt * (math.sin(half) / half if abs(half) > 1e-6 else 1.0 - half * half / 6.0)
    middle = yaw + half
    return x + chord * math.cos(middle), y + chord * math.sin(middle), yaw + w * dt


def clamp(value, limit):
    """``value`` limited to [-limit, limit]."""
    return max(-limit, min(limit, value))


def _ramp(current, target, up, down, dt):
    """Move ``current`` toward ``target``: at most ``up`` * dt away from zero, ``down`` * dt toward it."""
    delta = target - current
    accelerating = current * delta > 0 or current == 0.0
    step = (up if accelerating else down) * dt
    return current + clamp(delta, step)


class _Wheel(object):
    """One driven wheel: motor speed (rim m/s at nominal radius), angle, ripple, true radius."""

    def __init__(self, radius):
        self.radius = radius
        self.speed = 0.0
        self.angle = 0.0
        self.ripple = 0.0

    def ticks(self):
        """Encoder count, an integer as the Kobuki reports (wraps ignored)."""
        return int(math.floor(self.angle / (2.0 * math.pi) * TICKS_PER_REV))


class SimulatedKobuki(object):
    """A Kobuki base in a plane; see the module docstring. ``arena`` (optional) blocks motion.

    Public state: ``t`` (s), ``true_pose`` (Pose2D, world), ``true_twist`` ((v, w) true),
    ``odom`` (OdomState as kobuki_node reports), ``gyro_rate``, ``gyro_heading``,
    ``wheel_angles`` / ``wheel_speeds`` ((left, right), rad and rad/s), ``motor_power``,
    ``contacts`` (from the arena, or None), ``command_active`` (a command is being executed).
    """

    def __init__(self, profile, seed=0, arena=None, start=Pose2D(0.0, 0.0, 0.0)):
        self.profile = make_profile(profile)
        p = self.profile
        self._rng = random.Random(seed)
        self.arena = arena
        mean_radius = WHEEL_RADIUS * p['distance_scale']
        ratio = p['wheel_diameter_ratio']
        self._left = _Wheel(2.0 * mean_radius / (ratio + 1.0))
        self._right = _Wheel(2.0 * mean_radius * ratio / (ratio + 1.0))
        self._gyro_bias = self._rng.uniform(-p['gyro_bias_max'], p['gyro_bias_max'])
        self._common_ripple = 0.0
        self._steps = 0
        self._sensor_every = int(round(SENSOR_PERIOD / p['physics_dt']))
        self._timeout_every = int(round(TIMEOUT_CHECK_PERIOD / p['physics_dt']))
        self._cmd = (0.0, 0.0)
        self._cmd_time = None
        self._limited = (0.0, 0.0)
        self.motor_power = True
        self.true_pose = start
        self.true_twist = (0.0, 0.0)
        self._cycle_start_yaw = start.yaw
        self._cycle_distance = 0.0
        self.gyro_rate = 0.0
        self.gyro_heading = 0.0
        self._last_ticks = (self._left.ticks(), self._right.ticks())
        self._odom = [0.0, 0.0, 0.0]
        self._heading_offset = 0.0
        self._wheel_zero = (0, 0)
        self.odom = OdomState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        self.contacts = arena.contacts(start) if arena else None
        self.fallen = False

    # ------------------------------------------------------------------ inputs
    @property
    def t(self):
        """Sim time, s."""
        return self._steps * self.profile['physics_dt']

    @property
    def command_active(self):
        """True while a non-timed-out command is being executed."""
        return self._cmd_time is not None

    def command(self, v, w):
        """A velocity command arrives now: clamped to the Kobuki's limits; ValueError if not finite."""
        if not (math.isfinite(v) and math.isfinite(w)):
            raise ValueError('velocity command must be finite, got v=%r w=%r' % (v, w))
        self._cmd = (clamp(v, MAX_V), clamp(w, MAX_W))
        self._cmd_time = self.t

    def set_motor_power(self, on):
        """Motors on/off (kobuki_msgs/MotorPower); off drops the command and stops the wheels."""
        self.motor_power = bool(on)
        if not on:
            self._drop_command()

    def reset_odometry(self):
        """Zero the odometry pose, the gyro heading and the wheel angles, as kobuki_node's
        commands/reset_odometry does; the twist goes on (it is measured, not integrated)."""
        self._odom = [0.0, 0.0, 0.0]
        self._heading_offset = self.gyro_heading
        self.odom = self.odom._replace(x=0.0, y=0.0, yaw=0.0)
        self._wheel_zero = (self._left.ticks(), self._right.ticks())    # joint states from 0 too

    def place(self, pose):
        """Put the robot down at ``pose`` (Pose2D, world), as a person carrying it
        would: the wheels and the gyro do not count the move."""
        self.true_pose = Pose2D(*pose)
        self._cycle_start_yaw = self.true_pose.yaw
        if self.arena is not None:
            self.contacts = self.arena.contacts(self.true_pose)

    # ----------------------------------------------------------------- physics
    def step(self, dt):
        """Advance by ``dt`` s of sim time, a multiple of ``physics_dt``."""
        h = self.profile['physics_dt']
        n = int(round(dt / h))
        if n < 0 or abs(n * h - dt) > 1e-9:
            raise ValueError('step(dt=%r): dt must be a non-negative multiple of physics_dt=%r' % (dt, h))
        for _ in range(n):
            self._substep(h)

    def _drop_command(self):
        self._cmd = (0.0, 0.0)
        self._cmd_time = None

    def _substep(self, h):
        p = self.profile
        if self._steps % self._timeout_every == 0 and self._cmd_time is not None \
                and self.t - self._cmd_time > CMD_TIMEOUT + 1e-9:
            self._drop_command()
        self._steps += 1
        target = self._cmd if self.motor_power and not self.fallen else (0.0, 0.0)
        if p['acceleration_limiter']:
            lim = ACCEL_LIMITS
            target = (_ramp(self._limited[0], target[0], lim['v_up'], lim['v_down'], h),
                      _ramp(self._limited[1], target[1], lim['w_up'], lim['w_down'], h))
        self._limited = target
        self._actuate(target[0], target[1], h)
        if self._steps % self._sensor_every == 0:
            self._sense(self._sensor_every * h)

    def _actuate(self, v, w, h):
        """The wheels driven toward (v, w) for ``h`` s and the body moved (the physics;
        sim/mujoco_kobuki.py replaces it)."""
        p = self.profile
        if p['ripple_common'] > 0.0 and p['ripple_std'] > 0.0 and (v != 0.0 or w != 0.0):
            a = math.exp(-h / p['ripple_time'])
            self._common_ripple = self._common_ripple * a + self._rng.gauss(0.0, math.sqrt(1.0 - a * a))
        half = w * WHEEL_SEPARATION / 2.0
        self._drive_wheel(self._left, v - half, h)
        self._drive_wheel(self._right, v + half, h)
        self._move_body(h)

    def _drive_wheel(self, wheel, target, h):
        p = self.profile
        steady = 0.0
        if target != 0.0:
            magnitude = max(abs(target) * (1.0 - p['speed_droop'] * abs(target)) - p['friction_speed'], 0.0)
            steady = math.copysign(magnitude, target)
            if p['ripple_std'] > 0.0:
                a = math.exp(-h / p['ripple_time'])
                wheel.ripple = wheel.ripple * a + self._rng.gauss(0.0, math.sqrt(1.0 - a * a))
                common = p['ripple_common']
                ripple = math.sqrt(1.0 - common) * wheel.ripple + math.sqrt(common) * self._common_ripple
                steady += ripple * p['ripple_std'] / (1.0 + abs(target) / p['ripple_knee'])
        tau = p['motor_time_constant']
        wheel.speed = steady if tau <= 0.0 else wheel.speed + (steady - wheel.speed) * (1.0 - math.exp(-h / tau))
        wheel.angle += wheel.speed / WHEEL_RADIUS * h

    def _ground_speed(self, wheel):
        rim = wheel.speed / WHEEL_RADIUS * wheel.radius
        return rim * (1.0 - self.profile['slip_per_speed'] * abs(rim))

    def _move_body(self, h):
        left, right = self._ground_speed(self._left), self._ground_speed(self._right)
        v, w = (left + right) / 2.0, (right - left) / WHEEL_SEPARATION
        x, y, yaw = self.true_pose
        moved = Pose2D(*arc_motion(x, y, yaw, v, w, h))
        if self.fallen:
            moved = Pose2D(x, y, yaw)
        elif self.arena is not None:
            moved, self.contacts = self.arena.resolve(self.true_pose, moved)
            self.fallen = bool(self.contacts.wheel_drop)
        self._cycle_distance += math.hypot(moved.x - x, moved.y - y)
        self.true_twist = (v, w)
        self.true_pose = moved

    def _true_turn(self):
        """The body's true turn (rad) since the last sensor cycle, as the gyro feels it."""
        turn = self.true_pose.yaw - self._cycle_start_yaw
        self._cycle_start_yaw = self.true_pose.yaw
        return turn

    def _sense(self, period):
        p = self.profile
        true_rate = self._true_turn() / period
        self.gyro_rate = (true_rate * (1.0 + p['gyro_scale_error']) + self._gyro_bias
                          + (self._rng.gauss(0.0, p['gyro_noise_std']) if p['gyro_noise_std'] > 0 else 0.0))
        self.gyro_heading += self.gyro_rate * period
        ticks = (self._left.ticks(), self._right.ticks())
        metres_per_tick = 2.0 * math.pi * WHEEL_RADIUS / TICKS_PER_REV
        d_left = (ticks[0] - self._last_ticks[0]) * metres_per_tick
        d_right = (ticks[1] - self._last_ticks[1]) * metres_per_tick
        self._last_ticks = ticks
        distance = (d_left + d_right) / 2.0
        d_yaw_encoders = (d_right - d_left) / WHEEL_SEPARATION
        x, y, heading = self._odom
        self._odom = [x + distance * math.cos(heading + d_yaw_encoders / 2.0),
                      y + distance * math.sin(heading + d_yaw_encoders / 2.0),
                      self.gyro_heading - self._heading_offset]
        self.odom = OdomState(self._odom[0], self._odom[1], wrap_angle(self._odom[2]),
                              distance / period, self.gyro_rate, self.t)

    # ----------------------------------------------------------------- readers
    @property
    def wheel_angles(self):
        """(left, right) wheel angles, rad, as the encoders count them."""
        per_tick = 2.0 * math.pi / TICKS_PER_REV
        return ((self._left.ticks() - self._wheel_zero[0]) * per_tick,
                (self._right.ticks() - self._wheel_zero[1]) * per_tick)

    @property
    def wheel_speeds(self):
        """(left, right) wheel angular speeds, rad/s."""
        return (self._left.speed / WHEEL_RADIUS, self._right.speed / WHEEL_RADIUS)

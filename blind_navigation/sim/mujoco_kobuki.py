"""The Kobuki on the MuJoCo physics engine: the fake TurtleBot's physics base.

:class:`MujocoKobuki` is a :class:`sim.kobuki.SimulatedKobuki` whose physics is a
MuJoCo model (built here as MJCF): a 2.35 kg body (plus an optional payload with
its centre of mass off the axle), two velocity-servoed drive wheels (radius
0.035 m, 0.230 m apart, torque-limited) and two low-friction castor spheres, all
in contact with a floor from a world file (config/worlds: tile or carpet, a 1 cm
threshold, a 2 degree ramp). The commands, the 0.6 s timeout, kobuki_node's
acceleration limiter (always on here), the 50 Hz encoders (from the wheel joints)
and gyro (from the body's angular velocity) and kobuki_node's odometry are the
kinematic base's. The noise profile gives the sensor errors, the wheel radii
(``wheel_diameter_ratio``, ``distance_scale``) and
the motors' lag (``motor_time_constant``, on the servo's target); the speed droop,
ripple and slip terms are not used: slip comes from the contacts.

``mujoco`` is imported when a base is built (``base='kinematic'`` needs none):
from the interpreter's path, else from ``$BN_WS/venvs/sim`` (requirements/sim.txt, by install_deps.sh).
:func:`make_base` builds either base by name. Numbers and sources: docs/fake_turtlebot.md.
"""
import glob
import math
import os
import sys

from ..core.geometry import Pose2D, wrap_angle
from .config_dir import config_dir, load_named
from .kobuki import WHEEL_RADIUS, WHEEL_SEPARATION, SimulatedKobuki

BASES = ('kinematic', 'mujoco')
WORLD_DIR = config_dir('worlds')
BODY_MASS = 2.35              # kg, the Kobuki with its wheels
WHEEL_MASS = 0.1              # kg each (part of BODY_MASS)
WHEEL_TORQUE = 0.5            # N m, each wheel's motor torque limit (docs/fake_turtlebot.md)
CASTOR_RADIUS = 0.015         # m
CASTOR_X = 0.12               # m, front castor ahead of the axle (the rear one as far behind)
SUSPENSION_STIFFNESS = 1500.0 # N/m, each wheel's spring (its preload carries half the robot)
SUSPENSION_DAMPING = 10.0     # N s/m
CASTOR_GAP = 0.002            # m, castors above the floor when level: the wheels carry the weight
BODY_COM_X = -0.01            # m, the body's centre of mass behind the axle (rests on the rear castor)
SERVO_TIME = 0.02             # s, the wheel speed servo's time constant (a stiff PID)
TIMESTEP = 0.005              # s, MuJoCo's step (0.002 s: the same errors within ~0.1 % of the path, 1.6x the CPU)
#: Floors: (wheel friction, castor friction); castors sink into carpet and drag. MuJoCo takes
#: the larger friction of two geoms in contact: the floor's is the castors', the wheels' their own.
FLOORS = {'tile': (0.9, 0.03), 'carpet': (0.6, 0.15)}
WORLD_KEYS = ('description', 'floor', 'threshold', 'ramp')


_ENGINE = []                  # the mujoco module, once imported


def import_mujoco():
    """The ``mujoco`` module: from sys.path, else from the simulator's virtualenv."""
    if _ENGINE:
        return _ENGINE[0]
    try:
        import mujoco
        _ENGINE.append(mujoco)
        return mujoco
    except ImportError:
        pass
    here = os.path.dirname(os.path.abspath(os.path.realpath(__file__)))
    workspace = os.environ.get('BN_WS') or os.path.join(here, '..', '..', '.ws')
    pattern = os.path.join(workspace, 'venvs', 'sim', 'lib', 'python%d.%d' % sys.version_info[:2],
                           'site-packages')
    for site in glob.glob(pattern):
        if site not in sys.path:
            sys.path.append(site)
    try:
        import mujoco
    except ImportError as error:
        raise ImportError('the physics base needs mujoco (%s); install it with '
                          'scripts/install_deps.sh (make deps)' % error)
    _ENGINE.append(mujoco)
    return mujoco


def engine_name():
    """'MuJoCo <version>', for the fake's start line."""
    return 'MuJoCo %s' % import_mujoco().__version__


def load_world(name_or_path):
    """World dict: a name in config/worlds/ (``tile``, ``carpet``, ``threshold``, ``ramp``)
    or a YAML path; ValueError naming the key and the file when it is wrong."""
    path, world = load_named(WORLD_DIR, name_or_path, 'physics world')
    if not isinstance(world, dict) or set(world) - set(WORLD_KEYS):
        raise ValueError('%s: a world is a mapping of %s' % (path, ', '.join(WORLD_KEYS)))
    world.setdefault('floor', 'tile')
    if world['floor'] not in FLOORS:
        raise ValueError('%s: floor must be one of %s, got %r' % (path, sorted(FLOORS), world['floor']))
    for key, fields in (('threshold', ('x', 'height')), ('ramp', ('x', 'slope_deg', 'length'))):
        part = world.get(key)
        if part is not None and (not isinstance(part, dict) or sorted(part) != sorted(fields)
                                 or not all(isinstance(part[f], (int, float)) for f in fields)):
            raise ValueError('%s: %s needs the numbers %s' % (path, key, ', '.join(fields)))
    return world


def _features(world, floor_friction):
    """(MJCF geoms, assets) of the world's threshold and ramp (each across the whole floor)."""
    geoms, assets, friction = [], [], '%g 0.005 0.0001' % floor_friction
    threshold = world.get('threshold')
    if threshold:
        geoms.append('<geom name="threshold" type="capsule" size="%g" fromto="%g -20 0 %g 20 0" '
                     'friction="%s"/>' % (threshold['height'], threshold['x'], threshold['x'], friction))
    ramp = world.get('ramp')
    if ramp:      # a height field: no vertical edge at the foot or the crest to catch a wheel
        a, x0, length = math.radians(ramp['slope_deg']), ramp['x'], ramp['length']
        top, first, last, step = length * math.tan(a), x0 - 1.0, x0 + length + 20.0, 0.05
        columns = int(round((last - first) / step)) + 1
        heights = ' '.join('%.4f' % min(max((first + i * step - x0) / length, 0.0), 1.0)
                           for i in range(columns))
        geoms.append('<geom name="ramp" type="hfield" hfield="ramp" pos="%g 0 0" friction="%s"/>'
                     % ((first + last) / 2.0, friction))
        assets.append('<hfield name="ramp" nrow="2" ncol="%d" size="%g 20 %g 0.05" elevation="%s %s"/>'
                      % (columns, (last - first) / 2.0, top, heights, heights))
    return geoms, assets


def model_xml(world, radii, payload=(0.0, 0.0, 0.0)):
    """The MJCF of the Kobuki on ``world``: wheel ``radii`` (left, right) m, ``payload``
    (kg, x, y m: its centre of mass, 0.1 m up)."""
    wheel_friction, castor_friction = FLOORS[world['floor']]
    mass, px, py = payload
    # the servo's gain from the inertia one wheel moves: half the robot at the rim
    inertia = (BODY_MASS + mass) / 2.0 * WHEEL_RADIUS ** 2
    kv = inertia / SERVO_TIME
    shell_mass = BODY_MASS - 2 * WHEEL_MASS - 2 * 0.01
    wheels, motors = [], []
    for side, sign, radius in (('left', 1, radii[0]), ('right', -1, radii[1])):
        wheels.append(
            '<body name="wheel_{s}" pos="0 {y:g} {r:g}"><joint name="wheel_{s}_drop" type="slide" '
            'axis="0 0 1" stiffness="{k:g}" springref="{ref:g}" range="-0.03 0.03" limited="true" '
            'damping="{c:g}"/><joint name="wheel_{s}_joint" type="hinge" axis="0 1 0"/><geom type="cylinder" size="{r:g} 0.0105" euler="90 0 0" mass="{m:g}" '
            'friction="{f:g} 0.005 0.0001"/></body>'.format(s=side, y=sign * WHEEL_SEPARATION / 2.0,
                                                           r=radius, m=WHEEL_MASS, f=wheel_friction, k=SUSPENSION_STIFFNESS,
                                                           ref=-(BODY_MASS + mass) * 9.81 / 2.0 / SUSPENSION_STIFFNESS,
                                                           c=SUSPENSION_DAMPING))
        motors.append('<velocity name="{s}_motor" joint="wheel_{s}_joint" kv="{kv:g}" '
                      'forcelimited="true" forcerange="-{t:g} {t:g}"/>'.format(s=side, kv=kv, t=WHEEL_TORQUE))
    castors = ''.join('<geom name="{n}_castor" type="sphere" size="{r:g}" pos="{x:g} 0 {z:g}" mass="0.01" '
                      'friction="0 0 0"/>'.format(n=n, r=CASTOR_RADIUS, x=x, z=CASTOR_RADIUS + CASTOR_GAP)
                      for n, x in (('front', CASTOR_X), ('rear', -CASTOR_X)))
    features, assets = _features(world, castor_friction)
    load = ('<geom name="payload" type="sphere" size="0.03" pos="%g %g 0.1" mass="%g" contype="0" '
            'conaffinity="0"/>' % (px, py, mass)) if mass > 0 else ''
    return ('<mujoco model="kobuki"><option timestep="{dt:g}" integrator="implicitfast" cone="elliptic" impratio="10"/>'
            '<asset>{assets}</asset><worldbody><geom name="floor" type="plane" size="0 0 1" friction="{wf:g} 0.005 0.0001"/>{feat}'
            '<body name="base" pos="0 0 0"><freejoint name="root"/>'
            '<geom name="shell" type="cylinder" size="0.175 0.04" pos="{cx:g} 0 0.08" mass="{sm:g}" '
            'contype="0" conaffinity="0"/>{castors}{load}{wheels}</body></worldbody>'
            '<actuator>{motors}</actuator></mujoco>').format(
                dt=TIMESTEP, wf=castor_friction, feat=''.join(features), assets=''.join(assets),
                sm=shell_mass, cx=BODY_COM_X, castors=castors, load=load, wheels=''.join(wheels), motors=''.join(motors))


def _yaw(quaternion):
    w, x, y, z = quaternion
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


class MujocoKobuki(SimulatedKobuki):
    """The Kobuki on MuJoCo (module docstring). ``world``: a name or path (:func:`load_world`);
    ``payload``: (kg, x, y) of an extra mass, its centre ``x``, ``y`` m from the axle's middle.
    Same public state and methods as :class:`SimulatedKobuki`; ``arena`` is not supported."""

    def __init__(self, profile, seed=0, arena=None, start=Pose2D(0.0, 0.0, 0.0), world='tile',
                 payload=(0.0, 0.0, 0.0)):
        if arena is not None:
            raise ValueError('the mujoco base has no arena (bumper, cliff, wheel drop): use base kinematic')
        super(MujocoKobuki, self).__init__(profile, seed=seed, start=start)
        self.profile['acceleration_limiter'] = True     # kobuki_node's limiter: the Kobuki's acceleration
        mujoco = import_mujoco()
        self.world = load_world(world)
        xml = model_xml(self.world, (self._left.radius, self._right.radius), tuple(payload))
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        self._wheel_qpos = [self.model.jnt_qposadr[self.model.joint('wheel_%s_joint' % s).id]
                            for s in ('left', 'right')]
        self._wheel_dof = [self.model.jnt_dofadr[self.model.joint('wheel_%s_joint' % s).id]
                           for s in ('left', 'right')]
        self._substeps = int(round(self.profile['physics_dt'] / TIMESTEP))
        self._turn = 0.0                                # body z rotation since the last sensor cycle
        self._targets = [0.0, 0.0]                      # rim speeds the servos follow, m/s
        self.place(start)
        mujoco.mj_step(self.model, self.data, nstep=int(round(0.5 / TIMESTEP)))   # settle on the floor
        self._read_state()
        self._turn = 0.0
        self._last_ticks = (self._left.ticks(), self._right.ticks())

    def place(self, pose):
        """Put the robot down at ``pose`` (Pose2D, world), at rest; the sensors do not count it."""
        pose = Pose2D(*pose)
        if not hasattr(self, 'data'):
            super(MujocoKobuki, self).place(pose)
            return
        qpos = self.data.qpos
        qpos[0], qpos[1] = pose.x, pose.y
        qpos[3:7] = (math.cos(pose.yaw / 2.0), 0.0, 0.0, math.sin(pose.yaw / 2.0))
        self.data.qvel[:] = 0.0
        import_mujoco().mj_forward(self.model, self.data)
        self._unwrapped = pose.yaw
        self._read_state()

    def _actuate(self, v, w, h):
        half, tau = w * WHEEL_SEPARATION / 2.0, self.profile['motor_time_constant']
        for index, target in enumerate((v - half, v + half)):      # the motors' lag, as the kinematic base's
            goal = self._targets[index]
            goal = target if tau <= 0.0 else goal + (target - goal) * (1.0 - math.exp(-h / tau))
            self._targets[index] = goal
            self.data.ctrl[index] = goal / WHEEL_RADIUS
        rate_before = self.data.qvel[5]
        import_mujoco().mj_step(self.model, self.data, nstep=self._substeps)
        self._turn += 0.5 * (rate_before + self.data.qvel[5]) * h
        self._read_state()

    def _read_state(self):
        """true_pose (yaw unwrapped), true_twist and the wheels from MuJoCo's state."""
        qpos, qvel = self.data.qpos, self.data.qvel
        yaw = _yaw(qpos[3:7])
        previous = getattr(self, '_unwrapped', yaw)
        self._unwrapped = previous + wrap_angle(yaw - previous)
        self.true_pose = Pose2D(float(qpos[0]), float(qpos[1]), self._unwrapped)
        forward = qvel[0] * math.cos(yaw) + qvel[1] * math.sin(yaw)
        self.true_twist = (float(forward), float(qvel[5]))
        for wheel, adr, dof in zip((self._left, self._right), self._wheel_qpos, self._wheel_dof):
            wheel.angle, wheel.speed = float(qpos[adr]), float(qvel[dof]) * WHEEL_RADIUS

    def _true_turn(self):
        turn, self._turn = self._turn, 0.0
        return turn


def make_base(base, profile, seed=0, arena=None, world='tile', payload=(0.0, 0.0, 0.0)):
    """A base by name (:data:`BASES`): ``kinematic`` (sim/kobuki.py; ``world`` and ``payload``
    unused) or ``mujoco`` (:class:`MujocoKobuki`)."""
    if base == 'kinematic':
        return SimulatedKobuki(profile, seed=seed, arena=arena)
    if base == 'mujoco':
        return MujocoKobuki(profile, seed=seed, arena=arena, world=world, payload=payload)
    raise ValueError('unknown base %r (known: %s)' % (base, ', '.join(BASES)))

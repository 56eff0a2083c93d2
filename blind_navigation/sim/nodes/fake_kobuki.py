#!/usr/bin/env python3
"""Fake Kobuki base node: runs sim/kobuki.SimulatedKobuki and owns the sim clock.

``~base`` chooses the robot: ``kinematic`` (sim/kobuki.py) or ``mujoco`` (the
physics base, sim/mujoco_kobuki.py, on the floor ``~physics_world`` with an optional
payload); it logs one line naming MuJoCo and its version at start.

Speaks kobuki_node's topics: subscribes ``mobile_base/commands/velocity``
(Twist), ``commands/motor_power``, ``commands/reset_odometry`` (as kobuki_node: pose,
gyro heading and wheel angles from zero, twist continuous); publishes at
50 Hz ``odom`` (+ TF ``odom`` -> ``base_footprint``), ``mobile_base/sensors/imu_data``,
``joint_states``, ``ground_truth/odom`` (frame ``world``), Kobuki safety events on
``mobile_base/events/{bumper,cliff,wheel_drop}`` when it meets the arena,
``mobile_base/sensors/core`` (kobuki_msgs/SensorState: ``battery`` in 0.1 V from
sim/battery.py's model, ``~battery`` V at start; ``charger`` and ``bumper`` from the dock and
the arena) at :data:`CORE_RATE`, with a ``~dock`` (sim/dock.py: ``start`` or ``x y yaw``)
``mobile_base/sensors/dock_ir`` at 50 Hz, and ``/clock`` at ``rtf`` x wall time. Stamps are sim time (launch with use_sim_time).

With ``~wall_time`` it runs as a robot does: no /clock, ``rtf`` 1, every stamp
the wall time its period was due (launch with use_sim_time false), so what a
node costs is measured without the /clock every node under sim time receives
(evaluation/cost.py).

Test rig (no kobuki_node counterpart): a std_msgs/Float64 on ``~odometry_gap``
(``mobile_base/odometry_gap``) starts an odometry gap of that many seconds of
sim time: no ``odom`` and no ``odom`` TF until it has passed, as when a loaded
computer or the base driver stalls; the base keeps moving and every other
stream (IMU, joint states, ground truth, /clock) goes on. Odometry comes back
with the pose the base reached meanwhile. 0 ends a running gap; a negative or
non-finite length is refused with an error. Each gap is logged where it starts
and ends. A std_msgs/Float64 on ``~rtf`` (``mobile_base/rtf``) sets the clock's
real-time factor from the next tick on (> 0; refused with an error under
``~wall_time`` or ``~clock`` false), so a test runs what it does not time faster.
A std_msgs/Empty on ``~restart`` (``mobile_base/restart``) is a restart of this
node, as a kill and relaunch: ``/clock`` (and every stamp) from 0 again and the
odometry from the origin (as ``reset_odometry``); the robot stays where it
stands (the ground truth goes on). Refused with an error where this node
publishes no /clock. A std_msgs/String on ``~move_dock`` (``mobile_base/move_dock``) moves the
dock (a world event): ``x y yaw``, or ``start`` behind the robot where it stands now.

``/clock`` is global, so on a master shared by several fakes (two robots in two
namespaces) only one publishes it; the others run with ``~clock`` false and step
their base with that clock, stamping from the time they joined it.
"""
import faulthandler
import math
import signal
import sys
import threading
import time
import warnings

import rospy
import tf2_ros
import yaml
from geometry_msgs.msg import TransformStamped, Twist
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Imu, JointState
from std_msgs.msg import Empty, Float64, Header, String

from blind_navigation.ros import kobuki_msgs_compat as kobuki_msgs
from blind_navigation.sim.arena import arena_from_dict
from blind_navigation.sim.battery import SIM_BATTERY_DEFAULTS, SimBattery
from blind_navigation.sim.dock import bumper_bits, charger_state, dock_from_spec
from blind_navigation.sim.kobuki import ODOM_POSE_COVARIANCE, SENSOR_PERIOD, CommandLag, load_profile
from blind_navigation.sim.mujoco_kobuki import engine_name, make_base
from blind_navigation.ros.clock import LoopClock
from blind_navigation.ros.common import set_pose, subscribe
from blind_navigation.sim.node_common import GROUND_TRUTH, load_params

DBL_MAX = sys.float_info.max
#: Kobuki sensor names (sim/arena.py) -> kobuki_msgs' index constants.
BUMPER_INDEX = {'left': 0, 'center': 1, 'right': 2}
CLIFF_INDEX = {'left': 0, 'center': 1, 'right': 2}
WHEEL_INDEX = {'left': 0, 'right': 1}
#: Hz of mobile_base/sensors/core (the Kobuki streams it at 50 Hz; 10 Hz spares the CPU at a high
#: rtf and is enough for the battery: the layer's watch debounces over seconds, core/battery.py)
CORE_RATE = 10.0
# The 50 Hz x rtf streams are written in the publishing thread (rospy's synchronous
# mode): a queue thread per connection costs more CPU than the write itself.
SYNCHRONOUS = None
warnings.filterwarnings('ignore', message='The publisher should be created with an explicit')


class FakeKobuki(object):
    """The base and the clock. Params (DEFAULTS): ``rtf`` real-time factor; ``seed``; ``noise``
    profile name or path; ``world`` YAML with ``arena``/``obstacles`` ('' = open floor);
    ``clock_period`` s of sim time per /clock message (divides 0.02); ``odom_frame``,
    ``base_frame``, ``world_frame``, ``imu_frame``; ``publish_tf``; ``stats_period`` s of wall
    time between CPU/rtf log lines (0 = never); ``clock``: publish /clock at ``rtf`` (true) or
    follow another node's /clock (false; ``rtf`` then unused); ``wall_time``: no /clock, stamps
    in wall time, paced at ``rtf`` 1 (the only rtf it accepts; ``clock`` then unused); ``base``
    kinematic or mujoco; with mujoco ``physics_world`` (config/worlds name or path) and a payload
    of ``payload_mass`` kg centred ``payload_x``, ``payload_y`` m from the axle's middle;
    ``dock`` (sim/dock.dock_from_spec); ``battery`` V; ``command_lag`` s the velocity commands
    reach the base late (sim/kobuki.CommandLag: a loaded robot's late commands; 0: at once).
    """
    DEFAULTS = {'rtf': 1.0, 'seed': 0, 'noise': 'ideal', 'world': '', 'clock_period': 0.01,
                'odom_frame': 'odom', 'base_frame': 'base_footprint', 'world_frame': 'world',
                'imu_frame': 'gyro_link', 'publish_tf': True, 'stats_period': 0.0, 'clock': True,
                'wall_time': False, 'base': 'kinematic', 'physics_world': 'tile', 'payload_mass': 0.0,
                'payload_x': 0.0, 'payload_y': 0.0, 'dock': '', 'command_lag': 0.0}
    DEFAULTS.update(SIM_BATTERY_DEFAULTS)

    def __init__(self):
        self.params = p = load_params(self.DEFAULTS)
        if not p.rtf > 0:
            raise ValueError('~rtf must be > 0, got %r' % p.rtf)
        if p.wall_time and p.rtf != 1.0:
            raise ValueError('~wall_time runs at real time: ~rtf must be 1, got %r' % p.rtf)
        if p.wall_time and rospy.get_param('/use_sim_time', False):
            raise ValueError('~wall_time stamps in wall time: /use_sim_time must be false')
        ticks = SENSOR_PERIOD / p.clock_period
        if p.clock_period <= 0 or abs(ticks - round(ticks)) > 1e-6:
            raise ValueError('~clock_period %r must divide %.2f s' % (p.clock_period, SENSOR_PERIOD))
        self.sensor_every = int(round(ticks))
        arena = None
        if p.world:
            with open(p.world) as stream:
                arena = arena_from_dict(yaml.safe_load(stream), p.world)
        self.base = make_base(p.base, load_profile(p.noise), seed=int(p.seed), arena=arena,
                              world=p.physics_world,
                              payload=(float(p.payload_mass), float(p.payload_x), float(p.payload_y)))
        if p.base == 'mujoco':
            rospy.loginfo('fake_kobuki: physics base on %s (world %s, payload %g kg at %g, %g m)',
                          engine_name(), p.physics_world, p.payload_mass, p.payload_x, p.payload_y)
        self.battery = SimBattery(float(p.battery), float(p.battery_drain), float(p.battery_motion),
                                  float(p.battery_noise), seed=int(p.seed) + 7)
        self.lag = CommandLag(float(p.command_lag)) if p.command_lag else None
        self.lock = threading.Lock()
        self.ticks = 0
        self.clock_zero = 0.0            # base time (s) the clock last (re)started from
        self.odometry_gap_until = None   # base time (s) a running odometry gap ends, or None
        publishes_clock = p.clock and not p.wall_time
        self.clock_pub = rospy.Publisher('/clock', Clock, queue_size=SYNCHRONOUS) if publishes_clock else None
        self.odom_pub = rospy.Publisher('odom', Odometry, queue_size=SYNCHRONOUS)
        self.truth_pub = rospy.Publisher(GROUND_TRUTH, Odometry, queue_size=SYNCHRONOUS)
        self.imu_pub = rospy.Publisher('mobile_base/sensors/imu_data', Imu, queue_size=SYNCHRONOUS)
        self.joint_pub = rospy.Publisher('joint_states', JointState, queue_size=SYNCHRONOUS)
        self.event_pubs = {
            'bumper': rospy.Publisher('mobile_base/events/bumper', kobuki_msgs.BumperEvent, queue_size=10),
            'cliff': rospy.Publisher('mobile_base/events/cliff', kobuki_msgs.CliffEvent, queue_size=10),
            'wheel_drop': rospy.Publisher('mobile_base/events/wheel_drop', kobuki_msgs.WheelDropEvent,
                                          queue_size=10)}
        self.core_pub = rospy.Publisher('mobile_base/sensors/core', kobuki_msgs.SensorState, queue_size=10)
        self.core_every = int(round(1.0 / (CORE_RATE * p.clock_period)))
        self.tf = tf2_ros.TransformBroadcaster() if p.publish_tf else None
        self.dock = dock_from_spec(p.dock, self.base.true_pose)
        self.ir_pub = rospy.Publisher('mobile_base/sensors/dock_ir', kobuki_msgs.DockInfraRed,
                                      queue_size=SYNCHRONOUS) if self.dock else None
        self._messages()
        self._contacts = self.base.contacts
        subscribe('mobile_base/commands/velocity', Twist, self.on_velocity, queue_size=10)
        subscribe('mobile_base/commands/motor_power', kobuki_msgs.MotorPower, self.on_motor_power)
        subscribe('mobile_base/commands/reset_odometry', Empty, self.on_reset_odometry)
        subscribe('~odometry_gap', Float64, self.on_odometry_gap)
        self.new_rtf = None              # an rtf asked for on ~rtf, not yet in use
        subscribe('~rtf', Float64, self.on_rtf)
        subscribe('~restart', Empty, self.on_restart)
        subscribe('~move_dock', String, self.on_move_dock)

    def _messages(self):
        """Build the periodic messages once; the loop only updates their fields."""
        p = self.params
        self.odom_msg = Odometry()
        self.odom_msg.header.frame_id, self.odom_msg.child_frame_id = p.odom_frame, p.base_frame
        for index, value in ODOM_POSE_COVARIANCE.items():
            self.odom_msg.pose.covariance[index] = value
        self.truth_msg = Odometry()
        self.truth_msg.header.frame_id, self.truth_msg.child_frame_id = p.world_frame, p.base_frame
        self.imu_msg = Imu()
        self.imu_msg.header.frame_id = p.imu_frame
        self.imu_msg.orientation_covariance = [DBL_MAX, 0, 0, 0, DBL_MAX, 0, 0, 0, 0.05]
        self.imu_msg.angular_velocity_covariance = [DBL_MAX, 0, 0, 0, DBL_MAX, 0, 0, 0, 0.05]
        self.imu_msg.linear_acceleration_covariance = [-1.0, 0, 0, 0, 0, 0, 0, 0, 0]
        self.joint_msg = JointState(name=['wheel_left_joint', 'wheel_right_joint'])
        self.transform = TransformStamped()
        self.transform.header.frame_id, self.transform.child_frame_id = p.odom_frame, p.base_frame

    # ---------------------------------------------------------------- inputs
    def on_velocity(self, msg):
        try:
            with self.lock:
                if self.lag is not None:
                    self.lag.push(self.base.t, (msg.linear.x, msg.angular.z))
                else:
                    self.base.command(msg.linear.x, msg.angular.z)
        except ValueError as error:
            rospy.logerr_throttle(1.0, 'fake_kobuki: ignored velocity command: %s' % error)

    def on_motor_power(self, msg):
        with self.lock:
            self.base.set_motor_power(msg.state == kobuki_msgs.MotorPower.ON)
        rospy.loginfo('fake_kobuki: motors %s', 'on' if self.base.motor_power else 'off')

    def on_reset_odometry(self, _msg):
        with self.lock:
            self.base.reset_odometry()
        rospy.loginfo('fake_kobuki: odometry reset')

    def on_odometry_gap(self, msg):
        length = msg.data
        if not (math.isfinite(length) and length >= 0.0):
            rospy.logerr('fake_kobuki: ignored %s: a gap of %r s (give seconds of sim time >= 0)',
                         rospy.resolve_name('~odometry_gap'), length)
            return
        with self.lock:
            self.odometry_gap_until = self.base.t + length
        rospy.logwarn('fake_kobuki: odometry gap: no odom and no odom TF for %.2f s from t %.2f s',
                      length, rospy.get_time())

    def on_rtf(self, msg):
        p = self.params
        if not (math.isfinite(msg.data) and msg.data > 0.0) or p.wall_time or not p.clock:
            rospy.logerr('fake_kobuki: ignored %s %r (needs > 0, and this node publishing /clock)',
                         rospy.resolve_name('~rtf'), msg.data)
            return
        self.new_rtf = msg.data

    def on_restart(self, _msg):
        p = self.params
        if p.wall_time or not p.clock:
            rospy.logerr('fake_kobuki: ignored %s (this node publishes no /clock)',
                         rospy.resolve_name('~restart'))
            return
        with self.lock:
            was = self.base.t - self.clock_zero
            self.clock_zero = self.base.t
            self.base.reset_odometry()
        rospy.logwarn('fake_kobuki: restarted at t %.2f s: /clock from 0, odometry from the origin '
                      '(the robot stays where it is)', was)

    def on_move_dock(self, msg):
        with self.lock:
            try:
                dock = dock_from_spec(msg.data, self.base.true_pose) if self.dock else None
                why = '' if dock else 'needs a dock at launch (~dock) and a pose: x y yaw or start'
            except ValueError as error:
                dock, why = None, str(error)
            if dock:
                self.dock = dock
        if why:
            rospy.logerr('fake_kobuki: ignored %s %r (%s)', rospy.resolve_name('~move_dock'), msg.data, why)
        else:
            rospy.loginfo('fake_kobuki: dock moved to %.3f %.3f %.3f', *dock.pose)

    def _odometry_paused(self):
        """True while an odometry gap runs (called with the lock held); logs its end."""
        until = self.odometry_gap_until
        if until is None:
            return False
        if self.base.t < until - 1e-9:
            return True
        self.odometry_gap_until = None
        rospy.logwarn('fake_kobuki: odometry gap over: odom and odom TF again from t %.2f s',
                      rospy.get_time())
        return False

    # ---------------------------------------------------------------- output
    def publish_sensors(self, stamp):
        base = self.base
        odom, truth = base.odom, base.true_pose
        msg = self.odom_msg
        msg.header.stamp = stamp
        set_pose(msg.pose.pose, odom.x, odom.y, odom.yaw)
        msg.twist.twist.linear.x, msg.twist.twist.angular.z = odom.v, odom.w
        paused = self._odometry_paused()
        if not paused:
            self.odom_pub.publish(msg)
        if self.tf is not None and not paused:
            t = self.transform
            t.header.stamp = stamp
            t.transform.translation.x, t.transform.translation.y = odom.x, odom.y
            t.transform.rotation = msg.pose.pose.orientation
            self.tf.sendTransform(t)
        imu = self.imu_msg
        imu.header.stamp = stamp
        imu.orientation = msg.pose.pose.orientation
        imu.angular_velocity.z = base.gyro_rate
        self.imu_pub.publish(imu)
        joints = self.joint_msg
        joints.header.stamp = stamp
        joints.position, joints.velocity = list(base.wheel_angles), list(base.wheel_speeds)
        self.joint_pub.publish(joints)
        gt = self.truth_msg
        gt.header.stamp = stamp
        set_pose(gt.pose.pose, truth.x, truth.y, truth.yaw)
        gt.twist.twist.linear.x, gt.twist.twist.angular.z = base.true_twist
        self.truth_pub.publish(gt)
        if self.dock:
            self.ir_pub.publish(kobuki_msgs.DockInfraRed(header=Header(stamp=stamp),
                                                         data=self.dock.ir(truth)))
        self.publish_events()

    def publish_core(self, stamp):
        """kobuki_msgs/SensorState: the battery (0.1 V, sim/battery.py), the charger (the dock's
        contacts, sim/dock.py) and the bumper bits."""
        contact = self.dock.contact(self.base.true_pose) if self.dock else None
        self.battery.charger = charger_state(bool(contact and contact.docked), self.battery.volts)
        msg = kobuki_msgs.SensorState(battery=self.battery.reading(), charger=self.battery.charger,
                                      time_stamp=int(self.base.t * 1000.0) % 65536,
                                      bumper=bumper_bits(self.base.contacts) | (contact.bumper if contact else 0))
        msg.header.stamp = stamp
        self.core_pub.publish(msg)

    def publish_events(self):
        """One event message per sensor whose state changed, as kobuki_node does."""
        old, new = self._contacts, self.base.contacts
        if new is None or old == new:
            return
        specs = (('bumper', kobuki_msgs.BumperEvent, BUMPER_INDEX, 'bumper'),
                 ('cliff', kobuki_msgs.CliffEvent, CLIFF_INDEX, 'sensor'),
                 ('wheel_drop', kobuki_msgs.WheelDropEvent, WHEEL_INDEX, 'wheel'))
        for field, cls, index, slot in specs:
            before, after = getattr(old, field), getattr(new, field)
            for name in sorted(before ^ after):
                event = cls(state=1 if name in after else 0)
                setattr(event, slot, index[name])
                self.event_pubs[field].publish(event)
                rospy.logwarn('fake_kobuki: %s %s %s', field, name, 'on' if name in after else 'off')
        self._contacts = new

    def step(self, start):
        """One clock period of physics; the sensors when their period is due. Returns the
        sim time reached: ``start`` (s) plus the base's own time."""
        with self.lock:
            due = self.lag.due(self.base.t) if self.lag is not None else None
            if due is not None:
                self.base.command(*due)
            self.base.step(self.params.clock_period)
            self.battery.step(self.params.clock_period, *self.base.true_twist)
            self.ticks += 1
            now = rospy.Time.from_sec(start + self.base.t - self.clock_zero)
            if self.ticks % self.sensor_every == 0:
                self.publish_sensors(now)
            if self.ticks % self.core_every == 0:
                self.publish_core(now)
        return now

    def run(self):
        """Step physics and publish the clock, paced to rtf x wall time; with ``~wall_time``
        stamp in wall time instead of publishing a clock; or, with ``~clock`` false, follow
        the clock another node publishes."""
        p = self.params
        if not p.clock and not p.wall_time:
            self.follow_clock()
            return
        wall_period = p.clock_period / p.rtf
        start = time.monotonic()
        # wall time of the monotonic clock's zero: a tick is stamped with the wall time it was due
        wall_offset = time.time() - start if p.wall_time else None
        tick = 0
        stats_start, cpu_start = start, time.process_time()
        while not rospy.is_shutdown():
            if self.new_rtf is not None:            # a new pace from now on
                p.rtf, self.new_rtf = self.new_rtf, None
                wall_period, start, tick = p.clock_period / p.rtf, time.monotonic(), 0
                rospy.loginfo('fake_kobuki: rtf %g from t %.2f s', p.rtf, self.base.t)
            tick += 1
            if wall_offset is None:
                self.clock_pub.publish(Clock(clock=self.step(0.0)))
            else:                                    # stamped when this period was due
                self.step(wall_offset + start - wall_period)
            delay = start + tick * wall_period - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            elif delay < -0.5:                       # cannot keep up: do not try to catch up later
                start -= delay
                rospy.logwarn_throttle(10.0, 'fake_kobuki: behind real time x %.1f' % p.rtf)
            if p.stats_period > 0 and time.monotonic() - stats_start >= p.stats_period:
                stats_start, cpu_start = self.log_stats(stats_start, cpu_start)

    def follow_clock(self):
        """Step the base as far as /clock has gone, then sleep (sim time) until it goes on.
        The base starts at the first clock time seen (a period boundary), standing still."""
        p = self.params
        rospy.loginfo('fake_kobuki: following the /clock of another node')
        while not rospy.is_shutdown() and rospy.get_rostime().is_zero():
            time.sleep(0.01)
        start = p.clock_period * int(rospy.get_time() / p.clock_period)
        clock = LoopClock('fake_kobuki (following /clock)', then='the base goes on from where it was')
        while not rospy.is_shutdown():
            target = rospy.get_time() - start
            while self.base.t + p.clock_period <= target + 1e-9 and not rospy.is_shutdown():
                self.step(start)
            try:
                start -= clock.sleep(p.clock_period)    # a jump back: stamps go on from the new time
            except rospy.ROSInterruptException:
                return

    def log_stats(self, wall_start, cpu_start):
        wall, cpu = time.monotonic(), time.process_time()
        rospy.loginfo('fake_kobuki: sim t %.1f s, cpu %.0f %% of one core over %.1f s wall',
                      self.base.t, 100.0 * (cpu - cpu_start) / (wall - wall_start), wall - wall_start)
        return wall, cpu


def main():
    rospy.init_node('mobile_base')
    # a stop that hung twice in CI (no exit on SIGINT, killed 17 s later): roslaunch's SIGTERM
    # leaves every thread's stack on stderr, then rospy's handler runs
    faulthandler.register(signal.SIGTERM, chain=True)
    try:
        node = FakeKobuki()
    except (ValueError, OSError, ImportError) as error:
        rospy.logfatal('fake_kobuki: %s', error)
        sys.exit(1)
    node.run()


if __name__ == '__main__':
    main()

"""rostest helper: an ideal differential base inside the test process, the simulated
Kobuki (blind_navigation/sim/kobuki.py) with the ``ideal`` profile (an exact
unicycle). It executes the Twists on ``cmd_topic`` as a Kobuki does (clamped,
dropped 0.6 s after the last one), publishes its true pose and twist as
nav_msgs/Odometry on /odom at 50 Hz (ideal odometry: the odometry frame is the
world) and records every Twist. ``x``, ``y``, ``yaw`` (settable: the base is put
there), ``v``, ``w``: its pose and twist. ``publish_odom = False`` cuts the
odometry; :meth:`FakeBase.turn` turns it in place as an operator would (the pi turn the
layer checks, without a rotate_pi node)."""
import math
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from blind_navigation.core.geometry import Pose2D, quaternion_from_yaw, wrap_angle
from blind_navigation.sim.kobuki import SimulatedKobuki, load_profile

import waiting

RATE = 50.0


class FakeBase(object):
    def __init__(self, cmd_topic='/cmd_vel_mux/input/teleop', x=0.0, y=0.0, yaw=0.0):
        self._base = SimulatedKobuki(load_profile('ideal'), start=Pose2D(x, y, yaw))
        self.publish_odom = True
        self._turn_w = self._turn_left = 0.0     # a turn in place under way (rad/s, rad)
        self.odom_stamps = []       # sim time of each odometry published
        self.commands = []          # (receipt time s, v, w)
        self._lock = threading.Lock()
        self._pub = rospy.Publisher('/odom', Odometry, queue_size=5)
        rospy.Subscriber(cmd_topic, Twist, self._on_cmd, queue_size=10)
        self._timer = rospy.Timer(rospy.Duration(1.0 / RATE), self._tick)

    x = property(lambda self: self._base.true_pose.x, lambda self, x: self._place(x=x))
    y = property(lambda self: self._base.true_pose.y, lambda self, y: self._place(y=y))
    yaw = property(lambda self: wrap_angle(self._base.true_pose.yaw),
                   lambda self, yaw: self._place(yaw=yaw))
    v = property(lambda self: self._base.true_twist[0])
    w = property(lambda self: self._base.true_twist[1])

    def _place(self, **changes):
        with self._lock:
            self._base.place(self._base.true_pose._replace(**changes))

    def wait_for_listeners(self, count=1, timeout=20.0):
        """Until ``count`` nodes subscribe to its /odom, then a few odometry periods, so
        they hold odometry before a test drives them (a goal sent earlier is refused)."""
        waiting.wait_for(lambda: self._pub.get_num_connections() >= count,
                         '%d subscriber(s) of the fake base\'s /odom' % count, timeout)
        rospy.sleep(3.0 / RATE)

    def turn(self, angle, rate=1.0, timeout=30.0):
        """Turn in place by ``angle`` rad at ``rate`` rad/s (odometry follows, as a real
        turn; commands are ignored meanwhile); returns when done."""
        with self._lock:
            self._turn_w = math.copysign(rate, angle)
            self._turn_left = abs(angle)
        waiting.wait_for(lambda: self._turn_left == 0.0, 'the base turned by %.2f rad' % angle,
                         timeout)

    def drive(self, v, seconds):
        """Drive straight at ``v`` m/s for ``seconds`` of sim time (an operator's drive while
        recording: a mission asked home before the robot moved ends home at once), then stop."""
        until = rospy.get_time() + seconds
        while rospy.get_time() < until:
            with self._lock:
                self._base.command(v, 0.0)
            rospy.sleep(0.1)
        with self._lock:
            self._base.command(0.0, 0.0)
        rospy.sleep(0.5)

    def cut_odometry(self):
        """Stops publishing odometry (``publish_odom = True`` resumes it); returns the
        sim time of the last odometry published, taken with the tick locked out, so no
        odometry follows it."""
        with self._lock:
            self.publish_odom = False
            return self.odom_stamps[-1]

    def _on_cmd(self, msg):
        with self._lock:
            self.commands.append((rospy.get_time(), msg.linear.x, msg.angular.z))
            if self._turn_left == 0.0:
                self._base.command(msg.linear.x, msg.angular.z)

    def _tick(self, _event):
        dt = 1.0 / RATE
        now = rospy.get_time()
        with self._lock:
            if self._turn_left > 0.0:
                step = min(abs(self._turn_w) * dt, self._turn_left)
                self._base.command(0.0, math.copysign(step / dt, self._turn_w))
                self._turn_left = max(0.0, self._turn_left - step)
            self._base.step(dt)
            if self._turn_left == 0.0 and self._turn_w:
                self._base.command(0.0, 0.0)      # the turn is over: stand still
                self._turn_w = 0.0
            msg = Odometry()
            msg.header.stamp = rospy.Time.now()
            msg.header.frame_id = 'odom'
            pose, (v, w) = self._base.true_pose, self._base.true_twist
            msg.pose.pose.position.x, msg.pose.pose.position.y = pose.x, pose.y
            q = msg.pose.pose.orientation
            q.x, q.y, q.z, q.w = quaternion_from_yaw(pose.yaw)
            msg.twist.twist.linear.x, msg.twist.twist.angular.z = v, w
            if not self.publish_odom:
                return
            self.odom_stamps.append(now)
        try:
            self._pub.publish(msg)
        except rospy.ROSException:
            pass  # test node shutting down

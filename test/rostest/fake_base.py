"""rostest helper: an ideal differential base inside the test process. It
integrates the latest Twist on ``cmd_topic`` (dropped after 0.6 s, as Kobuki)
and publishes nav_msgs/Odometry on /odom at 50 Hz; it records every Twist.
``publish_odom = False`` cuts the odometry; ``stuck = True`` stops the wheels
(commands are still recorded); :meth:`FakeBase.turn` turns it in place as an
operator would (the pi turn the layer checks, without a rotate_pi node)."""
import math
import threading

import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry

from blind_navigation.core.geometry import quaternion_from_yaw, wrap_angle

import waiting

RATE = 50.0
COMMAND_TIMEOUT = 0.6


class FakeBase(object):
    def __init__(self, cmd_topic='/cmd_vel_mux/input/teleop', x=0.0, y=0.0, yaw=0.0):
        self.x, self.y, self.yaw = x, y, yaw
        self.v = self.w = 0.0
        self.publish_odom = True
        self.stuck = False
        self._turn_w = self._turn_left = 0.0     # a turn in place under way (rad/s, rad)
        self.odom_stamps = []       # sim time of each odometry published
        self.commands = []          # (receipt time s, v, w)
        self._lock = threading.Lock()
        self._pub = rospy.Publisher('/odom', Odometry, queue_size=5)
        rospy.Subscriber(cmd_topic, Twist, self._on_cmd, queue_size=10)
        self._timer = rospy.Timer(rospy.Duration(1.0 / RATE), self._tick)

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

    def _on_cmd(self, msg):
        with self._lock:
            self.commands.append((rospy.get_time(), msg.linear.x, msg.angular.z))

    def _tick(self, _event):
        dt = 1.0 / RATE
        now = rospy.get_time()
        with self._lock:
            if self._turn_left > 0.0:
                self.v, self.w = 0.0, self._turn_w
                step = min(abs(self._turn_w) * dt, self._turn_left)
                self._turn_left = max(0.0, self._turn_left - step)
                self.w = math.copysign(step / dt, self._turn_w)
            elif self.commands and now - self.commands[-1][0] < COMMAND_TIMEOUT and not self.stuck:
                self.v, self.w = self.commands[-1][1:]
            else:
                self.v = self.w = 0.0
            self.x += self.v * dt * math.cos(self.yaw + self.w * dt / 2)
            self.y += self.v * dt * math.sin(self.yaw + self.w * dt / 2)
            self.yaw = wrap_angle(self.yaw + self.w * dt)
            msg = Odometry()
            msg.header.stamp = rospy.Time.now()
            msg.header.frame_id = 'odom'
            msg.pose.pose.position.x, msg.pose.pose.position.y = self.x, self.y
            q = msg.pose.pose.orientation
            q.x, q.y, q.z, q.w = quaternion_from_yaw(self.yaw)
            msg.twist.twist.linear.x, msg.twist.twist.angular.z = self.v, self.w
            if not self.publish_odom:
                return
            self.odom_stamps.append(now)
        try:
            self._pub.publish(msg)
        except rospy.ROSException:
            pass  # test node shutting down

"""rostest helper: an ideal differential base inside the test process. It
integrates the latest Twist on ``cmd_topic`` (dropped after 0.6 s, as Kobuki)
and publishes nav_msgs/Odometry on /odom at 50 Hz; it records every Twist.
``publish_odom = False`` cuts the odometry; ``stuck = True`` stops the wheels
(commands are still recorded)."""
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

    def _on_cmd(self, msg):
        with self._lock:
            self.commands.append((rospy.get_time(), msg.linear.x, msg.angular.z))

    def _tick(self, _event):
        dt = 1.0 / RATE
        now = rospy.get_time()
        with self._lock:
            if self.commands and now - self.commands[-1][0] < COMMAND_TIMEOUT and not self.stuck:
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

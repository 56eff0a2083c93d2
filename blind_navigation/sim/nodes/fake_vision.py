#!/usr/bin/env python3
"""Fake RGB-D camera and RTAB-Map-like visual odometry of the fake TurtleBot, with failures.

Publishes images of a panorama turning with the true heading and their camera_info,
``rtabmap/odom`` (truth plus sim/visual_odometry drift) and, while subscribed,
``rtabmap/odom_info_lite``. Vision fails at ``vision_fail_at``, after the mission, or
on ``fake_turtlebot/set_vision``: ``dark`` (black images, VO lost), ``stall`` (nothing
published) or ``lost`` (VO lost: RTAB-Map's null pose, covariances 9999, no TF).
"""
import math

import numpy
import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Bool
from std_srvs.srv import SetBool, SetBoolResponse

from blind_navigation import names
from blind_navigation.core.geometry import Pose2D, yaw_from_quaternion
from blind_navigation.sim.odom_info import OdomInfo
from blind_navigation.sim.visual_odometry import VO_DRIFT_DEFAULTS, VO_RATE, DriftingOdometry
from blind_navigation.ros.common import shutting_down, set_pose, subscribe
from blind_navigation.sim.node_common import GROUND_TRUTH, MISSION_DONE, SET_VISION, load_params
from blind_navigation.ros.odometry import RECEIVE_QUEUE

MODES = ('dark', 'stall', 'lost')
LOST_COVARIANCE = 9999.0
TRACKING_COVARIANCE = 1e-4
DIAGONAL = (0, 7, 14, 21, 28, 35)
PANORAMA_COLUMNS = 720


class FakeVision(object):
    """Params (DEFAULTS): ``rate`` Hz; ``width``, ``height`` image size; ``seed``; ``vision_fail_at``
    sim s ('' = never); ``vision_fail_after_mission`` sim s after mission_driver/done ('' = never);
    ``vision_failure`` mode; ``scale_error_std``, ``yaw_drift_per_metre``,
    ``yaw_drift_per_radian`` (sim/visual_odometry); ``odom_frame``, ``base_frame``,
    ``camera_frame``; ``publish_tf``.
    """
    DEFAULTS = dict(VO_DRIFT_DEFAULTS, rate=VO_RATE, width=80, height=60, seed=0,
                    vision_fail_at='', vision_fail_after_mission='', vision_failure='dark', odom_frame='vo_odom',
                    base_frame='vo_base_footprint', camera_frame='camera_rgb_optical_frame',
                    publish_tf=True)

    def __init__(self):
        self.params = p = load_params(self.DEFAULTS)
        if p.vision_failure not in MODES:
            raise ValueError('~vision_failure must be one of %s, got %r' % (MODES, p.vision_failure))
        self.fail_at = float(p.vision_fail_at) if str(p.vision_fail_at).strip() else None
        if str(p.vision_fail_after_mission).strip():
            self.fail_after_mission = float(p.vision_fail_after_mission)
            subscribe(MISSION_DONE, Bool, self.on_mission_done, queue_size=1)
        self.failed = False
        self.truth = None
        self.drift = DriftingOdometry(int(p.seed) + 1, p.scale_error_std, p.yaw_drift_per_metre,
                                      p.yaw_drift_per_radian)
        rng = numpy.random.RandomState(int(p.seed))
        columns = rng.randint(40, 255, size=(1, PANORAMA_COLUMNS, 3)).astype(numpy.uint8)
        shade = numpy.linspace(0.5, 1.0, p.height).reshape(p.height, 1, 1)
        self.panorama = (numpy.repeat(columns, p.height, axis=0) * shade).astype(numpy.uint8)
        self.black = bytes(p.width * p.height * 3)
        self.image_pub = rospy.Publisher('camera/rgb/image_rect_color', Image, queue_size=5)
        self.info_pub = rospy.Publisher('camera/rgb/camera_info', CameraInfo, queue_size=5)
        self.odom_pub = rospy.Publisher('rtabmap/odom', Odometry, queue_size=10)
        self.odom_info_pub = rospy.Publisher(names.VO_ODOM_INFO, OdomInfo, queue_size=10)
        self.tf = tf2_ros.TransformBroadcaster() if p.publish_tf else None
        rospy.Service(SET_VISION, SetBool, self.on_set_vision)
        self.period = 1.0 / p.rate
        self.next_frame = None
        subscribe(GROUND_TRUTH, Odometry, self.on_truth, queue_size=RECEIVE_QUEUE)  # every pose

    def on_truth(self, msg):
        """Frames are clocked by the base's 50 Hz true pose stamps: one frame per ``period``
        of sim time, never skipped when the machine is loaded (a timer would drop them)."""
        q = msg.pose.pose.orientation
        self.truth = Pose2D(msg.pose.pose.position.x, msg.pose.pose.position.y,
                            yaw_from_quaternion(q.x, q.y, q.z, q.w))
        now = msg.header.stamp.to_sec()
        if self.next_frame is None or now < self.next_frame - self.period:   # first, or the clock went back
            self.next_frame = now
        while self.next_frame <= now + 1e-9:
            try:
                self.on_frame(rospy.Time.from_sec(self.next_frame))
            except rospy.ROSException:
                if not shutting_down():   # topics close in a pre-shutdown hook
                    raise
                return      # at shutdown the camera topics close before the base stops
            self.next_frame += self.period

    def on_mission_done(self, msg):
        if msg.data and self.fail_at is None and not self.failed:
            self.fail_at = rospy.get_time() + self.fail_after_mission
            rospy.loginfo('fake_vision: the operator is done; vision fails at sim t %.2f s',
                          self.fail_at)

    def on_set_vision(self, request):
        self.failed = not request.data
        message = 'vision %s' % ('restored' if request.data else 'failed (%s)' % self.params.vision_failure)
        rospy.logwarn('fake_vision: %s', message)
        return SetBoolResponse(success=True, message=message)

    def on_frame(self, stamp):
        if self.fail_at is not None and stamp.to_sec() >= self.fail_at:
            self.fail_at = None
            self.failed = True
            rospy.logwarn('fake_vision: vision failed (%s) at sim t %.2f s', self.params.vision_failure,
                          stamp.to_sec())
        mode = self.params.vision_failure if self.failed else None
        if mode == 'stall':
            return
        image = self.image(stamp, dark=(mode == 'dark'))
        self.image_pub.publish(image)
        self.info_pub.publish(CameraInfo(header=image.header, height=image.height, width=image.width))
        self.odom_pub.publish(self.lost_odometry(stamp) if mode else self.tracked_odometry(stamp))
        if self.odom_info_pub.get_num_connections():
            info = OdomInfo(lost=bool(mode), matches=0 if mode else 150, inliers=0 if mode else 100)
            info.header.stamp, info.header.frame_id = stamp, self.params.odom_frame
            self.odom_info_pub.publish(info)

    def image(self, stamp, dark):
        p = self.params
        msg = Image(height=p.height, width=p.width, encoding='rgb8', step=p.width * 3)
        msg.header.stamp, msg.header.frame_id = stamp, p.camera_frame
        if dark:
            msg.data = self.black
        else:
            first = int(-self.truth.yaw / (2.0 * math.pi) * PANORAMA_COLUMNS) % PANORAMA_COLUMNS
            columns = numpy.arange(first, first + p.width) % PANORAMA_COLUMNS
            msg.data = self.panorama[:, columns, :].tobytes()
        return msg

    def _odometry(self, stamp, covariance):
        msg = Odometry()
        msg.header.stamp, msg.header.frame_id = stamp, self.params.odom_frame
        msg.child_frame_id = self.params.base_frame
        for index in DIAGONAL:
            msg.pose.covariance[index] = covariance
            msg.twist.covariance[index] = covariance
        return msg

    def lost_odometry(self, stamp):
        """RTAB-Map's lost convention: zero pose, null quaternion, covariances 9999, no TF."""
        msg = self._odometry(stamp, LOST_COVARIANCE)
        msg.pose.pose.orientation.w = 0.0
        return msg

    def tracked_odometry(self, stamp):
        pose = self.drift.update(self.truth)
        msg = self._odometry(stamp, TRACKING_COVARIANCE)
        set_pose(msg.pose.pose, pose.x, pose.y, pose.yaw)
        if self.tf is not None:
            transform = TransformStamped()
            transform.header = msg.header
            transform.child_frame_id = msg.child_frame_id
            transform.transform.translation.x, transform.transform.translation.y = pose.x, pose.y
            transform.transform.rotation = msg.pose.pose.orientation
            self.tf.sendTransform(transform)
        return msg


def main():
    rospy.init_node('fake_vision')
    try:
        FakeVision()
    except ValueError as error:
        rospy.logfatal('fake_vision: %s', error)
        raise SystemExit(1)
    rospy.spin()


if __name__ == '__main__':
    main()

"""The return's paths for RViz, latched (nav_msgs/Path): the route the return
will drive on ``blind_navigation/return_route`` and the poses driven so far on
``blind_navigation/return_path`` (one pose per ``spacing`` m of odometry).
"""
import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path

from blind_navigation import names
from blind_navigation.core.geometry import distance
from blind_navigation.ros.common import set_pose


def _pose(header, x, y, yaw):
    pose = PoseStamped(header=header)
    set_pose(pose.pose, x, y, yaw)
    return pose


class ReturnPaths(object):
    """Publishes the route and the driven path (``spacing``: m between driven poses)."""

    def __init__(self, spacing):
        self.spacing = spacing
        self.path_pub = rospy.Publisher(names.RETURN_PATH, Path, queue_size=1, latch=True)
        self.route_pub = rospy.Publisher(names.RETURN_ROUTE, Path, queue_size=1, latch=True)
        self.path = Path()

    def publish_route(self, route, frame_id):
        """The route (core/route.Route) the return will drive, in ``frame_id`` ('' : odom)."""
        msg = Path()
        msg.header.stamp, msg.header.frame_id = rospy.Time.now(), frame_id or 'odom'
        for index, (x, y) in enumerate(zip(route.x, route.y)):
            yaw = route.direction(min(index, route.vertices - 2)) if route.vertices > 1 else 0.0
            msg.poses.append(_pose(msg.header, x, y, yaw))
        self.route_pub.publish(msg)

    def clear(self):
        """A new mission: both paths empty (RViz drops the last mission's)."""
        self.path = Path()
        self.path.header.stamp, self.path.header.frame_id = rospy.Time.now(), 'odom'
        self.path_pub.publish(self.path)
        self.route_pub.publish(Path(header=self.path.header))

    def driven(self, stamp, frame_id, odom):
        """The robot is at ``odom`` (x, y, yaw) at ``stamp`` (s): a pose every ``spacing`` m."""
        poses = self.path.poses
        if poses and distance(poses[-1].pose.position.x, poses[-1].pose.position.y,
                              odom.x, odom.y) < self.spacing:
            return
        header = rospy.Header(stamp=rospy.Time.from_sec(stamp), frame_id=frame_id)
        poses.append(_pose(header, odom.x, odom.y, odom.yaw))
        self.path.header = header
        self.path_pub.publish(self.path)

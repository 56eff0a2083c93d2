"""The rig's nodes' rospy glue (the fake TurtleBot, the bench's observer): the rig's own
evaluation names, plain params, odometry messages as OdomStates, a node started or exited
on a bad param."""
import math

import rospy

from ..core.geometry import OdomState, yaw_from_quaternion
from ..core.params import REQUIRED

# the fake TurtleBot's evaluation names, relative (INTERFACE.md; names.py holds the layer's)
#: nav_msgs/Odometry, the true pose (frame world)
GROUND_TRUTH = 'ground_truth/odom'
#: service std_srvs/SetBool: false makes vision fail now, true restores it
SET_VISION = 'fake_turtlebot/set_vision'
#: std_msgs/Bool, latched: the scripted operator has played its mission
MISSION_DONE = 'mission_driver/done'
#: std_msgs/Empty, latched: the scripted operator may start (with its ``wait_for_go``)
MISSION_GO = 'mission_driver/go'


def load_params(defaults, namespace='~'):
    """Read each param ``namespace + name`` (private ``~name`` by default, ``~role/name``
    for a role hosted with others in one process), falling back to ``defaults[name]``;
    a :data:`REQUIRED` param that is not set is a ValueError naming it.

    Returns a plain object with one attribute per param and logs the values, so
    every node documents and reads its params the same way.
    """
    values = {name: rospy.get_param(namespace + name, default) for name, default in defaults.items()}
    missing = sorted(name for name, value in values.items() if value is REQUIRED)
    if missing:
        raise ValueError('%s not set (the launch files set %s; with rosrun give _%s:=...)'
                         % (', '.join(namespace + name for name in missing),
                            'them' if len(missing) > 1 else 'it', missing[0]))
    rospy.loginfo('%s params%s: %s', rospy.get_name(), '' if namespace == '~' else ' ' + namespace,
                  ', '.join('%s=%r' % item for item in sorted(values.items())))
    return type('Params', (object,), values)()


def odom_state_from_msg(msg):
    """OdomState from nav_msgs/Odometry; ValueError if the pose is NaN or the quaternion null."""
    pose, twist = msg.pose.pose, msg.twist.twist
    q = pose.orientation
    yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w)
    values = (pose.position.x, pose.position.y, twist.linear.x, twist.angular.z)
    if not all(math.isfinite(v) for v in values):
        raise ValueError('non-finite odometry (x, y, v, w) = %r' % (values,))
    return OdomState(pose.position.x, pose.position.y, yaw, twist.linear.x,
                     twist.angular.z, msg.header.stamp.to_sec())


def start_node(name, node_class, *args):
    """``rospy.init_node(name)`` then ``node_class(*args)``; a ValueError from the
    constructor (a bad param) is logged as fatal and exits with status 1."""
    rospy.init_node(name)
    try:
        return node_class(*args)
    except ValueError as error:
        rospy.logfatal('%s: %s', rospy.get_name(), error)
        raise SystemExit(1)

#!/usr/bin/env python3
"""back_travel_client: the paper's action client (section 3.3.7, Figure 6) and
the sole owner of the mission state.

State walk, published latched on /blind_navigation/state (std_msgs/String):
``idle`` -> ``recording`` (first /blind_navigation/footprint seen) ->
``rotating`` (/blind_navigation/vision_lost) -> ``returning``
(/blind_navigation/rotation_done true) -> ``home`` (every goal succeeded) or
``aborted`` (rotation failed, bad landmark file, no server, a goal failed).

When returning: loads ``landmark_file`` with core/store.load_landmarks (a bad
file aborts with the file and entry named; nothing is driven), waits for the
/blind_navigation/back_travel server (``server_timeout``), then sends the
landmarks in reverse order, one goal at a time, waiting for each result.
Publishes the odometry poses of the return on /blind_navigation/return_path.
"""
import os
import threading

import actionlib
import rospy
from actionlib.action_client import get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from std_msgs.msg import Bool, Empty, String

from blind_navigation.back_travel_ros import (BACK_TRAVEL_ACTION, FOOTPRINT_TOPIC,
                                              RETURN_PATH_TOPIC, ROTATION_DONE_TOPIC, STATE_TOPIC,
                                              VISION_LOST_TOPIC, LatestOdom)
from blind_navigation.core import state
from blind_navigation.core.geometry import distance, quaternion_from_yaw
from blind_navigation.core.store import LandmarkFileError, load_landmarks
from blind_navigation.msg import BackTravelAction, BackTravelGoal, Footprint
from blind_navigation.ros_common import load_params, start_node


class BackTravelClient(object):
    """Mission state machine and goal sender.

    Params (DEFAULTS): ``landmark_file``
    ('~/.ros/blind_navigation/landmarks.yaml', the recorder's symlink),
    ``odom_topic`` ('/odom', for return_path only), ``server_timeout`` (s, 10:
    wait for the action server), ``goal_timeout_factor`` (5) and
    ``goal_timeout_margin`` (s, 10): a goal's result is awaited at most
    factor * max(T, d / slowest_v) + margin, ``slowest_v`` (m/s, 0.03),
    ``path_spacing`` (m, 0.02 between return_path poses).
    """

    DEFAULTS = {
        'landmark_file': os.path.join('~', '.ros', 'blind_navigation', 'landmarks.yaml'),
        'odom_topic': '/odom',
        'server_timeout': 10.0,
        'goal_timeout_factor': 5.0,
        'goal_timeout_margin': 10.0,
        'slowest_v': 0.03,
        'path_spacing': 0.02,
    }

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        if not isinstance(p.landmark_file, str) or not p.landmark_file.strip():
            raise ValueError('~landmark_file must be a file path, got %r' % (p.landmark_file,))
        for name in ('server_timeout', 'goal_timeout_factor', 'slowest_v', 'path_spacing'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        self.state = None
        self._lock = threading.Lock()
        self._return = threading.Event()
        self.state_pub = rospy.Publisher(STATE_TOPIC, String, queue_size=1, latch=True)
        self.path_pub = rospy.Publisher(RETURN_PATH_TOPIC, Path, queue_size=1, latch=True)
        self.path = Path()
        self.client = actionlib.SimpleActionClient(BACK_TRAVEL_ACTION, BackTravelAction)
        self.set_state(state.IDLE)
        self.odom = LatestOdom(p.odom_topic, self._on_odom)
        rospy.Subscriber(FOOTPRINT_TOPIC, Footprint, self._on_footprint, queue_size=5)
        rospy.Subscriber(VISION_LOST_TOPIC, Empty, self._on_vision_lost, queue_size=1)
        rospy.Subscriber(ROTATION_DONE_TOPIC, Bool, self._on_rotation_done, queue_size=1)
        rospy.on_shutdown(self._on_shutdown)

    def set_state(self, new_state, reason=''):
        with self._lock:
            old, self.state = self.state, new_state
        log = rospy.logerr if new_state == state.ABORTED else rospy.loginfo
        log('%s: state %s -> %s%s', rospy.get_name(), old, new_state, ': ' + reason if reason else '')
        self.state_pub.publish(String(data=new_state))

    def _transition(self, expected, new_state, event):
        """Move to ``new_state`` if the state is ``expected``; log and ignore otherwise."""
        with self._lock:
            current = self.state
        if current != expected:
            if event != 'footprint':
                rospy.logwarn('%s: %s ignored in state %s', rospy.get_name(), event, current)
            return False
        self.set_state(new_state)
        return True

    def _on_footprint(self, _msg):
        self._transition(state.IDLE, state.RECORDING, 'footprint')

    def _on_vision_lost(self, _msg):
        self._transition(state.RECORDING, state.ROTATING, 'vision_lost')

    def _on_rotation_done(self, msg):
        if not msg.data:
            if self._transition(state.ROTATING, state.ABORTED, 'rotation_done false'):
                rospy.logerr('%s: the pi rotation failed; not travelling back', rospy.get_name())
            return
        if self._transition(state.ROTATING, state.RETURNING, 'rotation_done true'):
            self._return.set()

    def _on_odom(self, odom, msg):
        if self.state != state.RETURNING:
            return
        poses = self.path.poses
        if poses and distance(poses[-1].pose.position.x, poses[-1].pose.position.y,
                              odom.x, odom.y) < self.params.path_spacing:
            return
        pose = PoseStamped()
        pose.header = msg.header
        pose.pose.position.x, pose.pose.position.y = odom.x, odom.y
        q = pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(odom.yaw)
        poses.append(pose)
        self.path.header = msg.header
        self.path_pub.publish(self.path)

    def _on_shutdown(self):
        if self.state == state.RETURNING:
            self.client.cancel_all_goals()

    def spin(self):
        while not rospy.is_shutdown():
            if self._return.wait(0.2):
                self._return.clear()
                ok, reason = self.travel_back()
                if not rospy.is_shutdown():
                    self.set_state(state.HOME if ok else state.ABORTED, reason)

    def travel_back(self):
        """Figure 6: load, reverse, send goal by goal. Returns (ok, reason)."""
        p = self.params
        try:
            loaded = load_landmarks(os.path.expanduser(p.landmark_file))
        except LandmarkFileError as error:
            return False, 'landmark file unusable: %s' % error
        for warning in loaded.warnings:
            rospy.logwarn('%s: %s', rospy.get_name(), warning)
        rospy.loginfo('%s: %d landmarks, %.2f m, from %s; waiting for %s', rospy.get_name(),
                      len(loaded.landmarks), loaded.total_distance, loaded.path, BACK_TRAVEL_ACTION)
        if not self.client.wait_for_server(rospy.Duration(p.server_timeout)):
            return False, ('action server %s not available after %.0f s (is back_travel_server '
                           'running?)' % (BACK_TRAVEL_ACTION, p.server_timeout))
        goals = list(zip(loaded.labels, loaded.landmarks))[::-1]
        travelled = 0.0
        for number, (label, landmark) in enumerate(goals, 1):
            goal = BackTravelGoal(*landmark.as_list())
            self.client.send_goal(goal)
            allowed = (p.goal_timeout_factor * max(landmark.T, landmark.d / p.slowest_v)
                       + p.goal_timeout_margin)
            if not self.client.wait_for_result(rospy.Duration(allowed)):
                self.client.cancel_goal()
                return False, 'goal %d/%d (%s): no result within %.0f s' % (number, len(goals),
                                                                             label, allowed)
            status = self.client.get_state()
            if status != GoalStatus.SUCCEEDED:
                return False, 'goal %d/%d (%s) ended %s: %s' % (
                    number, len(goals), label, get_name_of_constant(GoalStatus, status),
                    self.client.get_goal_status_text())
            travelled += self.client.get_result().distance
        return True, 'travelled %.3f m over %d landmarks' % (travelled, len(goals))


def main():
    node = start_node('back_travel_client', BackTravelClient)
    node.spin()


if __name__ == '__main__':
    main()

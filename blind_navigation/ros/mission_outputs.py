"""What the mission owner shows and keeps beside the state: the RViz paths, the heading
correction, the return's progress file, its services' replies and its diagnostics."""
import os
from array import array

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from std_srvs.srv import TriggerResponse

from blind_navigation import names
from blind_navigation.core import mission_state as state
from blind_navigation.core.geometry import distance
from blind_navigation.core.mission import RECORDING
from blind_navigation.core.mission_files import mission_number
from blind_navigation.core.progress_keeper import MissionProgress
from blind_navigation.core.return_plan import plan_return
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import ros_home_file, set_pose
from blind_navigation.ros.heading_correction import (CALIBRATION_FILE, calibration_status,
                                                    correction_message, vo_status)
from blind_navigation.ros.landmark_saving import path_message


def reply(log, request, what, refusal, done):
    """The Trigger response of the service ``what``: refused for ``refusal``, else ``done``."""
    caller = request._connection_header.get('callerid', '?')
    if refusal is not None:
        log.warn('%s from %s %s', what, caller, refusal)
        return TriggerResponse(success=False, message=refusal)
    log.info('%s from %s: %s', what, caller, done)
    return TriggerResponse(success=True, message=done)


def add_diagnostics(owner, settings):
    """The ``owner``'s statuses (the recording's and the heading correction's when it records)."""
    add, m, odometry = owner.layer.diagnostics.add, lambda: owner.mission, owner.layer.odometry

    def odometry_status(stat):
        """The feed's age (stale: an error while driving, else a warning), its refusals."""
        level = diagnostics.ERROR if m().state in (state.ROTATING, state.RETURNING) else diagnostics.WARN
        diagnostics.age_status(stat, 'odometry', odometry.age(), settings['limits'].odom_timeout,
                               level, level, listening=odometry.listening())
        stat.add('refused messages', odometry.refused)
    add('mission', lambda stat: mission_status(stat, owner))
    add('odometry', odometry_status)
    add('landmark file', lambda stat: file_status(stat, owner.landmark_file, m().state))
    if not owner.RECORDS:    # the paper layout's saver and heading_correction report the rest
        return
    add('recording', lambda stat: owner.store.status(stat, m().phase != RECORDING))
    if not settings['heading_correction']:
        return
    heading = settings['standstill']
    path = ros_home_file(CALIBRATION_FILE, heading.gyro_calibration_file)
    add('heading correction: visual odometry', lambda stat: vo_status(
        stat, m().phase != RECORDING, owner.vo_heard, owner.vo_since, heading.vo_timeout,
        len(getattr(m().recording.fit, 'rows', ()))))
    add('heading correction: gyro calibration',
        lambda stat: calibration_status(stat, path, settings['scale_prior']))


def mission_status(stat, owner):
    """The mission's status: ``aborted`` an ERROR, ``recovered`` or a degraded mission a WARN."""
    m, mission_id = owner.mission, owner.layer.mission_id      # cached: no master call (an outage)
    for key, value in (('state', m.state), ('phase', m.phase), ('mission', mission_number(mission_id)),
                       ('mission id', mission_id), ('mission file', os.path.realpath(owner.landmark_file))):
        stat.add(key, value)
    current, reason, warnings = m.state, m.reason, owner.warnings()
    if current == state.ABORTED:
        stat.summary(diagnostics.ERROR, 'aborted: %s' % reason)
    elif current == state.RECOVERED:
        stat.summary(diagnostics.WARN, 'recovered: %s' % reason)
    elif warnings:
        stat.summary(diagnostics.WARN, '%s: %s' % (current, warnings))
    else:
        stat.summary(diagnostics.OK, '%s%s' % (current or '', ': ' + reason if reason else ''))


def file_status(stat, landmark_file, current):
    """The landmark file, the mission's file and its size (unreadable: an error mid-mission)."""
    stat.add('file', landmark_file)
    try:
        real = os.path.realpath(landmark_file)
        stat.add('mission file', real)
        stat.add('bytes', os.path.getsize(real))
        stat.summary(diagnostics.OK, os.path.basename(real))
    except OSError as error:
        level = diagnostics.ERROR if current in (state.RECORDING, state.ROTATING,
                                                 state.RETURNING) else diagnostics.OK
        stat.summary(level, 'no landmark file yet' if level == diagnostics.OK else
                     'landmark file unreadable: %s' % error.strerror)


class MissionOutputs(object):
    """The outputs of ``owner`` (a MissionOwner), brought up to date by :meth:`stepped`."""

    def __init__(self, owner):
        self.owner, self.odometry = owner, owner.layer.odometry
        self.path_pub = rospy.Publisher(names.RETURN_PATH, Path, queue_size=1, latch=True)
        self.route_pub = rospy.Publisher(names.RETURN_ROUTE, Path, queue_size=1, latch=True)
        if owner.RECORDS:   # else the paper layout's saver and heading_correction publish them
            self.recorded_pub = rospy.Publisher(names.RECORDED_PATH, Path, queue_size=1, latch=True)
            self.correction_pub = rospy.Publisher(names.HEADING_CORRECTION, HeadingCorrection,
                                                  queue_size=1, latch=True)
        self.progress = MissionProgress(owner.landmark_file, lambda: owner.layer.mission_id,
                                        lambda: self.odometry.frame_id, owner.log,
                                        changed=owner.publish_status)
        self._fresh()

    def _fresh(self):
        self.poses = array('d')     # x, y, yaw of the recording's start and every landmark
        self.shown = 0              # of them published
        self.correction = self.route = None
        self.path = Path()          # the return's poses driven, one per path_spacing m

    def first_state(self):
        """A return a previous run left: its KeptReturn or None (the mission aborted if it cannot go on)."""
        params = self.owner.params

        def position():
            odom = self.odometry.wait_fresh(params.odom_timeout, params.server_timeout)
            return [odom.x, odom.y] if odom is not None else None
        return self.progress.first_state(self.owner.mission, position, params)

    def new_mission(self):
        """Both RViz paths emptied, the last return's progress forgotten."""
        self._fresh()
        self.progress.forget()
        self.path.header.stamp, self.path.header.frame_id = rospy.Time.now(), 'odom'
        self.path_pub.publish(self.path)
        self.route_pub.publish(Path(header=self.path.header))
        if self.owner.RECORDS:
            self.recorded_pub.publish(path_message(self.poses, rospy.Time.now(), self.odometry.frame_id))

    def stepped(self, stored):
        """After a step that stored the landmarks ``stored`` (the owner's lock held)."""
        m = self.owner.mission
        if m.raw is not None and m.recording.started and not self.poses:
            self.poses.extend((m.raw.x, m.raw.y, m.raw.yaw))    # where the recording began
        for _ in stored:
            self.poses.extend((m.raw.x, m.raw.y, m.raw.yaw))
        if self.owner.RECORDS and len(self.poses) > self.shown and (
                self.recorded_pub.get_num_connections() or m.state != state.RECORDING):
            self.shown = len(self.poses)        # every pose once the recording is over
            self.recorded_pub.publish(path_message(self.poses, rospy.Time.now(), self.odometry.frame_id))
        if m.correction is not None and self.correction is None:
            self.correction = m.correction
            if m.config.heading_correction and self.owner.RECORDS:
                self.correction_pub.publish(correction_message(m.correction, m.reference,
                                                               self.odometry.frame_id))
        if getattr(m.drive, 'goals', None) is not None and self.route is None:
            route = self.route = m.route or plan_return(m.landmarks, m.anchor, self.owner.params, False)[0]
            poses = [value for index, (x, y) in enumerate(zip(route.x, route.y)) for value in (
                x, y, route.direction(min(index, route.vertices - 2)) if route.vertices > 1 else 0.0)]
            self.route_pub.publish(path_message(poses, rospy.Time.now(), self.odometry.frame_id or 'odom'))
        if m.state == state.RETURNING and m.last is not None:
            self._driven(m.raw.stamp, m.last)
        self.progress.update(m, self.route)

    def _driven(self, stamp, odom):
        """The robot is at ``odom`` at ``stamp`` (s): a pose every ``path_spacing`` m."""
        poses = self.path.poses
        if poses and distance(poses[-1].pose.position.x, poses[-1].pose.position.y,
                              odom.x, odom.y) < self.owner.params.path_spacing:
            return
        self.path.header = rospy.Header(stamp=rospy.Time.from_sec(stamp), frame_id=self.odometry.frame_id)
        poses.append(PoseStamped(header=self.path.header))
        set_pose(poses[-1].pose, odom.x, odom.y, odom.yaw)
        self.path_pub.publish(self.path)


"""What the mission owner (ros/mission_owner.py) shows and keeps of its core Mission beside
the state, as the default layer's roles do: the RViz paths (recorded_path, return_route,
return_path), the latched heading correction, the return's progress file
(core/progress_keeper.MissionProgress), its services' replies (go_home, cancel, new_mission;
refused naming the state: core/mission_state.*_refusal) and its diagnostics' parts.
"""
import os
from array import array

import rospy
from nav_msgs.msg import Path
from std_srvs.srv import TriggerResponse

from blind_navigation import names
from blind_navigation.core import mission_state as state
from blind_navigation.core.progress_keeper import MissionProgress
from blind_navigation.core.return_plan import plan_return
from blind_navigation.msg import HeadingCorrection
from blind_navigation.ros import diagnostics
from blind_navigation.ros.heading_correction import correction_message
from blind_navigation.ros.landmark_saving import path_message
from blind_navigation.ros.return_paths import ReturnPaths


def reply(log, request, what, refusal, done):
    """The Trigger response of the service ``what``: refused for ``refusal`` (WARN), else
    acknowledged with ``done`` (INFO); the log names the caller. Every mission owner's."""
    caller = request._connection_header.get('callerid', '?')
    if refusal is not None:
        log.warn('%s from %s %s', what, caller, refusal)
        return TriggerResponse(success=False, message=refusal)
    log.info('%s from %s: %s', what, caller, done)
    return TriggerResponse(success=True, message=done)


def mission_summary(stat, current, reason, warnings=''):
    """The mission status's level and line: ``aborted`` an ERROR, ``recovered`` (stopped away
    from home: someone takes the robot) or a degraded mission a WARN."""
    if current == state.ABORTED:
        stat.summary(diagnostics.ERROR, 'aborted: %s' % reason)
    elif current == state.RECOVERED:
        stat.summary(diagnostics.WARN, 'recovered: %s' % reason)
    elif warnings:
        stat.summary(diagnostics.WARN, '%s: %s' % (current, warnings))
    else:
        stat.summary(diagnostics.OK, '%s%s' % (current or '', ': ' + reason if reason else ''))


def odometry_status(stat, odometry, current, timeout):
    """The ``odometry`` feed's age (stale beyond ``timeout`` s: an error while the mission,
    ``current``, turns or returns, else a warning) and its refused messages."""
    level = diagnostics.ERROR if current in (state.ROTATING, state.RETURNING) else diagnostics.WARN
    diagnostics.age_status(stat, 'odometry', odometry.age(), timeout, level, level,
                           listening=odometry.listening())
    stat.add('refused messages', odometry.refused)


def file_status(stat, landmark_file, current):
    """The configured ``landmark_file``, the mission's file and its size (unreadable: an
    error while the mission, ``current``, records, turns or returns)."""
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
    """The outputs of ``owner`` (a MissionOwner: its mission, layer, params, log, landmark
    file and publish_status), brought up to date by :meth:`stepped` and :meth:`ending`."""

    def __init__(self, owner):
        self.owner, self.odometry = owner, owner.layer.odometry
        self.paths = ReturnPaths(owner.params.path_spacing)
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

    def first_state(self):
        """A return a previous run left: its core/resume.KeptReturn or None, the mission
        aborted if it cannot continue (MissionProgress.first_state)."""
        return self.progress.first_state(self.owner.mission, self._position, self.owner.params)

    def _position(self):
        odom = self.odometry.wait_fresh(self.owner.params.odom_timeout, self.owner.params.server_timeout)
        return [odom.x, odom.y] if odom is not None else None

    def new_mission(self):
        """Both RViz paths emptied, the last return's progress forgotten."""
        self._fresh()
        self.progress.forget()
        self.paths.clear()
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
            self.recorded_pub.publish(path_message(self.poses, rospy.Time.now(),
                                                   self.odometry.frame_id))
        if m.correction is not None and self.correction is None:
            self.correction = m.correction
            if m.config.heading_correction and self.owner.RECORDS:
                self.correction_pub.publish(correction_message(m.correction, m.reference,
                                                               self.odometry.frame_id))
        if getattr(m.drive, 'goals', None) is not None and self.route is None:
            self.route = m.route or plan_return(m.landmarks, m.anchor, self.owner.params, False)[0]
            self.paths.publish_route(self.route, self.odometry.frame_id)
        if m.state == state.RETURNING and m.last is not None:
            self.paths.driven(m.raw.stamp, self.odometry.frame_id, m.last)
        self.progress.update(m, self.route)

    def ending(self, new, reason):
        """The mission becomes ``new`` for ``reason`` (the owner's lock held)."""
        self.progress.ending(new, reason)

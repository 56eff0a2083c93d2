"""Saving path landmarks at sampling ticks: the one piece of code behind both of
the paper's recorder variants (section 3.3.3, Figure 4).

- topic variant: ``nodes/landmark_saver.py`` calls :meth:`LandmarkSaving.save`
  for each blind_navigation/PathSample;
- service variant: ``nodes/record_server.py`` calls it for each
  RecordLandmark request (sent by ``nodes/record_client.py``).

Either way the saver reads odometry itself (the state at the tick's stamp:
the latest odometry stamped no later than the tick), makes the landmark with
core/recorder.PathRecorder and appends it durably with core/store.LandmarkWriter
to a new time-stamped mission file that the ``landmark_file`` param (a symlink)
points at. Only that param chooses the file: nothing received over ROS names a
path. After each landmark it publishes the storage and the recorded path.
"""
import math
import os
import threading

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry, Path

from blind_navigation import names
from blind_navigation.core.geometry import quaternion_from_yaw
from blind_navigation.core.recorder import OdometryHistory, PathRecorder, storage_usage
from blind_navigation.core.store import LandmarkWriter, start_mission_file
from blind_navigation.msg import StorageUsage
from blind_navigation.ros.common import load_params, usable_odom_state


#: PathSample.command values: a regular tick, and the last partial cycle.
SAMPLE = 'sample'
FINAL = 'final'
COMMANDS = (SAMPLE, FINAL)

DEFAULT_LANDMARK_FILE = os.path.join('~', '.ros', 'blind_navigation', 'landmarks.yaml')


class LandmarkSaving(object):
    """Latest odometry -> landmark -> mission file, storage and recorded path.

    Params (DEFAULTS): ``odom_topic`` (nav_msgs/Odometry, '/odom'),
    ``landmark_file`` (the symlink to the mission's file,
    '~/.ros/blind_navigation/landmarks.yaml'), ``fsync`` (true: fsync every
    landmark, not just flush), ``odom_timeout`` (s of sim time; a sample taken
    with older odometry is saved with a warning, 1.0).
    """

    DEFAULTS = {
        'odom_topic': '/odom',
        'landmark_file': DEFAULT_LANDMARK_FILE,
        'fsync': True,
        'odom_timeout': 1.0,
        'odom_wait': 0.2,
    }

    def __init__(self, variant):
        p = self.params = load_params(self.DEFAULTS)
        if not isinstance(p.landmark_file, str) or not p.landmark_file.strip():
            raise ValueError('~landmark_file must be a file path, got %r' % (p.landmark_file,))
        if not isinstance(p.fsync, bool):
            raise ValueError('~fsync must be true or false, got %r' % (p.fsync,))
        self._lock = threading.Condition()
        self._history = OdometryHistory()
        self._odom_received = None
        self._frame = 'odom'
        self._start = None
        self.finished = False
        self.recorder = PathRecorder()
        path = start_mission_file(os.path.expanduser(p.landmark_file))
        self.writer = LandmarkWriter(path, fsync=p.fsync, metadata={
            'recorder': variant, 'odom_topic': p.odom_topic,
            'started_ros_time': round(rospy.Time.now().to_sec(), 3)})
        rospy.on_shutdown(self.writer.close)
        rospy.loginfo('%s: recording path landmarks into %s (%s -> %s)', rospy.get_name(), path,
                      p.landmark_file, os.path.basename(path))
        self.path_msg = Path()
        self.storage_pub = rospy.Publisher(names.STORAGE, StorageUsage, queue_size=10)
        self.path_pub = rospy.Publisher(names.RECORDED_PATH, Path, queue_size=1, latch=True)
        self.odom_sub = rospy.Subscriber(p.odom_topic, Odometry, self._on_odom, queue_size=100)

    def _on_odom(self, msg):
        state = usable_odom_state(msg, self.params.odom_topic)
        if state is None:
            return
        with self._lock:
            self._history.append(state)
            self._odom_received = rospy.Time.now()
            self._frame = msg.header.frame_id or self._frame
            self._lock.notify_all()

    def save(self, command, yaw, period, stamp):
        """Save the landmark of the tick at ``stamp`` (s); return ``(label, '')`` or
        ``('', why not)``. The first tick's start is the odometry at ``stamp - period``
        (when the publisher started), or the first odometry seen if that is later."""
        with self._lock:
            if command not in COMMANDS:
                return self._refuse('unknown command %r (expected one of %s)'
                                    % (command, ', '.join(COMMANDS)))
            if self.finished:
                return self._refuse('recording has finished (a final sample was saved)')
            if self._history.latest is None:
                return self._refuse('no valid odometry received on %s yet' % self.params.odom_topic)
            age = (rospy.Time.now() - self._odom_received).to_sec()
            if age > self.params.odom_timeout:
                rospy.logwarn_throttle(5.0, '%s: odometry on %s is %.1f s old' %
                                       (rospy.get_name(), self.params.odom_topic, age))
            if stamp > 0:
                self._lock.wait_for(lambda: self._history.latest.stamp >= stamp,
                                    timeout=self.params.odom_wait)
                odom = self._history.at(stamp)
            else:                               # an unstamped request: the latest odometry
                odom = self._history.latest
            if not self.recorder.started:
                valid = stamp > 0 and math.isfinite(period) and period > 0
                self._start = self._history.at(stamp - period) if valid else odom
                self.recorder.start(self._start)
            try:
                landmark = self.recorder.take(odom, yaw, period)
            except ValueError as error:
                return self._refuse('bad %s sample: %s' % (command, error))
            label = self.writer.append(landmark)
            self.finished = command == FINAL
        self._report(label, odom, landmark)
        if self.finished:
            self.writer.close()
            rospy.loginfo('%s: final landmark saved; recording finished', rospy.get_name())
        return label, ''

    def _refuse(self, reason):
        rospy.logwarn_throttle(2.0, '%s: landmark not saved: %s' % (rospy.get_name(), reason))
        return '', reason

    def _report(self, label, odom, landmark):
        """Publish the storage and the recorded path; log the storage."""
        now = rospy.Time.now()
        used = storage_usage(self.writer.count, self.writer.bytes, self.writer.total_distance)
        msg = StorageUsage(file=self.writer.path, landmarks=used.landmarks, bytes=used.bytes,
                        distance=used.distance, bytes_per_metre=used.bytes_per_metre)
        msg.header.stamp = now
        self.storage_pub.publish(msg)
        rospy.loginfo('%s: %s %s: %d landmarks, %d bytes, %.2f m, %.0f B/m', rospy.get_name(),
                      label, [round(value, 4) for value in landmark], used.landmarks, used.bytes,
                      used.distance, used.bytes_per_metre)
        if not self.path_msg.poses:
            self.path_msg.poses.append(self._pose(self._start, now))
        self.path_msg.poses.append(self._pose(odom, now))
        self.path_msg.header = self.path_msg.poses[-1].header
        self.path_pub.publish(self.path_msg)

    def _pose(self, odom, stamp):
        pose = PoseStamped()
        pose.header.stamp, pose.header.frame_id = stamp, self._frame
        pose.pose.position.x, pose.pose.position.y = odom.x, odom.y
        q = pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(odom.yaw)
        return pose

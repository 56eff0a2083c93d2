"""Saving path landmarks at sampling ticks: the one piece of code behind both of
the paper's recorder variants (section 3.3.3, Figure 4).

- topic variant: ros/landmark_saver.py calls :meth:`LandmarkSaving.save` for
  each blind_navigation/PathSample;
- service variant: ros/record_server.py calls it for each RecordLandmark
  request (sent by ros/record_client.py).

Either way the saver reads odometry itself from the process's shared feed (the
state at the tick's stamp: the latest odometry stamped no later than the tick;
odometry the plausibility gate refused is never used), makes the landmark with
core/recorder.PathRecorder and appends it durably with core/store.LandmarkWriter
to the mission's time-stamped file that the ``landmark_file`` param (a symlink)
points at (core/store.open_mission_file: a saver restarted within the same
mission, ``blind_navigation/mission_id``, continues that file after a gap
entry; a new mission starts a new file). Only that param chooses the file:
nothing received over ROS names a path; a ``landmark_file`` that is not a
regular file or a symlink to one is refused by name. After each landmark it
publishes the storage used (``blind_navigation/storage``, with the landmarks
lost to write failures and the last error) and, when someone listens, the
recorded path (``blind_navigation/recorded_path``, nav_msgs/Path for RViz).

A write failure (a full disk, an I/O error) is an ERROR in the log and in
``blind_navigation/storage`` (the mission's owner reports it in the mission
status and diagnostics); the landmark is lost, the file keeps whole lines, and
the next landmark is tried again. An odometry discontinuity (the gate
re-anchored on a reset) is a gap in the file: the next landmark measures ``d``
from the odometry after it.

Params (``layer.params``, role ``landmark_saver`` or ``record_server``):
``landmark_file`` (the symlink to the mission's file; empty:
``$ROS_HOME/blind_navigation/landmarks.yaml``), ``fsync`` (fsync every
landmark, not just flush), ``odom_timeout`` (s of sim time; a sample taken
with older odometry is saved with a warning), ``odom_wait`` (s of wall time a
sample waits for odometry covering its stamp).
"""
import math
import os
import threading
from array import array

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path

from blind_navigation import names
from blind_navigation.core.geometry import quaternion_from_yaw
from blind_navigation.core.files import StorageError
from blind_navigation.core.recorder import PathRecorder, storage_usage
from blind_navigation.core.store import open_mission_file
from blind_navigation.msg import StorageUsage
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import ros_home_file
from blind_navigation.ros.sampling_publisher import COMMANDS, FINAL

#: The landmark file when ``landmark_file`` is empty: under $ROS_HOME (default ~/.ros).
LANDMARK_FILE = os.path.join('blind_navigation', 'landmarks.yaml')


def landmark_file(param):
    """The configured landmark file: ``param``, or the default under $ROS_HOME."""
    if not isinstance(param, str):
        raise ValueError('~landmark_file must be a file path, got %r' % (param,))
    return os.path.abspath(os.path.expanduser(param.strip() or ros_home_file(LANDMARK_FILE)))


class LandmarkSaving(object):
    """Latest odometry -> landmark -> mission file, storage and recorded path."""

    DEFAULTS = {
        'landmark_file': '',    # the symlink to the mission's file (empty: under $ROS_HOME)
        'fsync': True,          # fsync every landmark (false: flush only)
        'odom_timeout': 1.0,    # s (sim); a sample with older odometry is saved with a warning
        'odom_wait': 0.2,       # s (wall) a sample waits for odometry covering its stamp
    }

    def __init__(self, layer, role, variant):
        p = self.params = layer.params(role, self.DEFAULTS)
        self.log = layer.logger(role)
        if not isinstance(p.fsync, bool):
            raise ValueError('~fsync must be true or false, got %r' % (p.fsync,))
        self.odometry = layer.odometry
        self.odometry.acquire(role)
        self.odometry.on_reanchor(self._on_reanchor)
        self._lock = threading.Lock()
        self._start = None
        self._poses = array('d')       # x, y, yaw of every landmark (and the start)
        self.finished = False
        self.error = ''
        self.recorder = PathRecorder()
        configured = landmark_file(p.landmark_file)
        self.writer = open_mission_file(configured, layer.mission_id, fsync=p.fsync, metadata={
            'recorder': variant, 'odom_topic': rospy.resolve_name(names.ODOM),
            'started_ros_time': round(rospy.Time.now().to_sec(), 3)})
        rospy.on_shutdown(self.writer.close)
        self.finished = self.writer.finished   # a continued mission file may be finished already
        path = self.writer.path
        if self.writer.resumed is not None:
            self.log.warn('restarted within the mission: continuing %s after its %d landmarks%s',
                          path, self.writer.count, ' (%d torn entries dropped)'
                          % self.writer.resumed.dropped if self.writer.resumed.dropped else '')
        else:
            self.log.info('recording path landmarks into %s (%s -> %s)', path, configured,
                          os.path.basename(path))
        self.storage_pub = rospy.Publisher(names.STORAGE, StorageUsage, queue_size=10)
        self.path_pub = rospy.Publisher(names.RECORDED_PATH, Path, queue_size=1, latch=True)
        layer.diagnostics.add('%s: recording' % role, self._diagnose)

    def _diagnose(self, stat):
        stat.add('file', self.writer.path)
        stat.add('landmarks', self.writer.count)
        stat.add('bytes', self.writer.bytes)
        stat.add('lost', self.writer.lost)
        if self.error:
            stat.summary(diagnostics.ERROR, '%d landmark(s) lost: %s' % (self.writer.lost, self.error))
        elif self.finished:
            stat.summary(diagnostics.OK, 'recording finished: %d landmarks' % self.writer.count)
        else:
            stat.summary(diagnostics.OK, 'recording: %d landmarks, %.2f m'
                         % (self.writer.count, self.writer.total_distance))

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
            if self.odometry.latest() is None:
                return self._refuse('no valid odometry received on %s yet'
                                    % rospy.resolve_name(names.ODOM))
            age = self.odometry.age()
            if age > self.params.odom_timeout:
                self.log.warn_throttle(5.0, 'odometry on %s is %.1f s old',
                                       rospy.resolve_name(names.ODOM), age)
            if stamp > 0:
                self.odometry.wait_for_stamp(stamp, self.params.odom_wait)
                odom = self.odometry.state_at(stamp)
            else:                               # an unstamped request: the latest odometry
                odom = self.odometry.latest()
            if not self.recorder.started:
                valid = stamp > 0 and math.isfinite(period) and period > 0
                self._start = self.odometry.state_at(stamp - period) if valid else odom
                self.recorder.start(self._start)
                self._poses.extend((self._start.x, self._start.y, self._start.yaw))
            try:
                landmark = self.recorder.take(odom, yaw, period)
            except ValueError as error:
                return self._refuse('bad %s sample: %s' % (command, error))
            try:
                label = self.writer.append(landmark)
            except StorageError as error:
                return self._write_failed(error)
            self._poses.extend((odom.x, odom.y, odom.yaw))
            self.finished = command == FINAL
            if self.finished:
                try:
                    self.writer.finish()
                except StorageError as error:
                    self._write_failed(error)
        self._report(label, landmark)
        if self.finished:
            self.log.info('final landmark saved; recording finished')
        return label, ''

    def _write_failed(self, error):
        """A landmark could not be written: ERROR, and the storage message says so."""
        self.error = str(error)
        self.log.error('LANDMARK LOST: %s', error)
        self._publish_storage(rospy.Time.now())
        return '', self.error

    def _on_reanchor(self, reason):
        """The odometry jumped and the gate took the new stream: the d chain breaks here."""
        with self._lock:
            if self.finished or not self.recorder.started:
                return
            latest = self.odometry.latest()
            self.recorder = PathRecorder()
            if latest is not None:
                self.recorder.start(latest)
            try:
                gap = self.writer.note_gap(reason)
                self.log.error('odometry discontinuity: %s noted in %s; the next landmark counts '
                               'from the new odometry', gap, self.writer.path)
            except StorageError as error:
                self._write_failed(error)

    def _refuse(self, reason):
        self.log.warn_throttle(2.0, 'landmark not saved: %s', reason)
        return '', reason

    def _report(self, label, landmark):
        """Publish the storage and (when listened to) the recorded path; log the storage."""
        now = rospy.Time.now()
        used = self._publish_storage(now)
        self.log.info('%s %s: %d landmarks, %d bytes, %.2f m, %.0f B/m', label,
                      [round(value, 4) for value in landmark], used.landmarks, used.bytes,
                      used.distance, used.bytes_per_metre)
        if self.path_pub.get_num_connections() > 0 or self.finished:
            self.path_pub.publish(self._path(now))

    def _publish_storage(self, now):
        used = storage_usage(self.writer.count, self.writer.bytes, self.writer.total_distance)
        msg = StorageUsage(file=self.writer.path, landmarks=used.landmarks, bytes=used.bytes,
                           distance=used.distance, bytes_per_metre=used.bytes_per_metre,
                           lost=self.writer.lost, error=self.error)
        msg.header.stamp = now
        self.storage_pub.publish(msg)
        return used

    def _path(self, stamp):
        path = Path()
        path.header.stamp, path.header.frame_id = stamp, self.odometry.frame_id
        for index in range(0, len(self._poses), 3):
            pose = PoseStamped()
            pose.header = path.header
            pose.pose.position.x, pose.pose.position.y = self._poses[index], self._poses[index + 1]
            q = pose.pose.orientation
            q.x, q.y, q.z, q.w = quaternion_from_yaw(self._poses[index + 2])
            path.poses.append(pose)
        return path

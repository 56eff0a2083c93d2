"""Saving path landmarks at sampling ticks: the code behind both of the paper's recorder
variants (3.3.3, Figure 4; ros/landmark_saver.py, ros/record_server.py).

Reads the odometry at the tick's stamp, makes the landmark (core/recorder.PathRecorder),
appends it durably to the mission's file, publishes ``storage`` and ``recorded_path``;
write failures, low space, gaps, the catch-up of a restarted saver and ``new_mission``'s
new file (docs/recording.md, "Saving", "File").
"""
import math
import os
import threading
from array import array

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path

from blind_navigation import names
from blind_navigation.core.geometry import OdomState
from blind_navigation.core.files import StorageError
from blind_navigation.core.recorder import PathRecorder, SpaceWatch, storage_usage
from blind_navigation.core.sample_log import START, answer_problem
from blind_navigation.core.landmark_format import SampleMark
from blind_navigation.core.mission_files import open_mission_file
from blind_navigation.core.role_params import LANDMARK_SAVING
from blind_navigation.msg import StorageUsage
from blind_navigation.srv import RecordedSamples
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import ros_home_file, set_pose, wait_wall
from blind_navigation.ros.sampling_publisher import COMMANDS, FINAL

#: The landmark file when ``landmark_file`` is empty: under $ROS_HOME (default ~/.ros).
LANDMARK_FILE = os.path.join('blind_navigation', 'landmarks.yaml')


def landmark_file(param):
    """The configured landmark file: ``param``, or the default under $ROS_HOME."""
    if not isinstance(param, str):
        raise ValueError('~landmark_file must be a file path, got %r' % (param,))
    return os.path.abspath(os.path.expanduser(param.strip() or ros_home_file(LANDMARK_FILE)))


def when_odometry(odometry, log, guard, log_period, start):
    """Call ``start()`` at once if the feed ``odometry`` has a state, else from a thread when
    it has one, warning every ``log_period`` s (wall) meanwhile. The sampling publisher waits
    for its subscribers, so it starts no recording that a recorder whose /odom subscription
    is still connecting would refuse the first samples of."""
    if odometry.latest() is not None:
        start()
        return

    def run():
        topic, waited = rospy.resolve_name(names.ODOM), False
        while not rospy.is_shutdown():
            odometry.state_at(0.0, wait=log_period)
            if odometry.latest() is not None:
                if waited:
                    log.info('odometry on %s: taking samples', topic)
                start()
                return
            waited = True
            log.warn('no odometry on %s yet: not taking samples until it comes', topic)
    threading.Thread(target=guard(run), name='recorder ready', daemon=True).start()


class LandmarkSaving(object):
    """Latest odometry -> landmark -> mission file, storage and recorded path."""

    SCHEMA = LANDMARK_SAVING

    def __init__(self, layer, role, variant):
        p = self.params = layer.params(role, self.SCHEMA)
        self.log = layer.logger(role)
        self.guard = layer.guard(role)      # the recorder's callbacks and threads
        self.odometry = layer.odometry
        self.odometry.acquire(role)   # reads back: at a stamp, waiting for it
        self.odometry.on_reanchor(self.guard(self._on_reanchor))
        self._lock = threading.Lock()
        self.variant, self.layer = variant, layer
        self.writer = None
        self._open()
        rospy.on_shutdown(lambda: self.writer.close())
        self.storage_pub = rospy.Publisher(names.STORAGE, StorageUsage, queue_size=10)
        self.path_pub = rospy.Publisher(names.RECORDED_PATH, Path, queue_size=1, latch=True)
        layer.mission.on_new_mission(self.guard(self._new_mission))
        layer.diagnostics.add('%s: recording' % role, lambda stat: recording_status(
            stat, self.writer, self.error, self.space.warning, self.finished))

    def when_ready(self, start):
        """Call ``start()`` (it subscribes to the samples, or serves them) once the feed has
        odometry (:func:`when_odometry`): a recorder takes samples only when it can save them."""
        when_odometry(self.odometry, self.log, self.guard, self.params.ready_log_period, start)

    def _open(self):
        """Open the mission's file (continued within the mission, else a new one) and start
        the path (lock held, or before the callbacks exist)."""
        self._poses = array('d')       # x, y, yaw of every landmark (and the start)
        self.error = ''
        self.recorder = PathRecorder()
        configured = landmark_file(self.params.landmark_file)
        self.mission_id = self.layer.current_mission_id()   # of the file open
        self.writer = open_mission_file(configured, self.mission_id, fsync=self.params.fsync, metadata={
            'recorder': self.variant, 'odom_topic': rospy.resolve_name(names.ODOM),
            'started_ros_time': round(rospy.Time.now().to_sec(), 3)})
        self.finished = self.writer.finished   # a continued mission file may be finished already
        path = self.writer.path
        self.space = SpaceWatch(os.path.dirname(path))
        self._check_space(rospy.Time.now())
        if self.writer.resumed is not None:
            self.log.warn('restarted within the mission: continuing %s after its %d landmarks%s',
                          path, self.writer.count, ' (%d torn entries dropped)'
                          % self.writer.resumed.dropped if self.writer.resumed.dropped else '')
        else:
            self.log.info('recording path landmarks into %s (%s -> %s)', path, configured,
                          os.path.basename(path))

    def _new_mission(self):
        with self._lock:
            self._follow_mission()

    def _follow_mission(self):
        """If ``new_mission`` set a new mission id (lock held): the old file closed as it is,
        the new mission's opened, RViz's path emptied; at the new mission's state or at its
        first sample, whichever reaches this process first."""
        if self.layer.current_mission_id() != self.mission_id:
            self.writer.close()
            self._open()
            self.path_pub.publish(path_message(self._poses, rospy.Time.now(), self.odometry.frame_id))

    def save(self, command, yaw, period, stamp, sample=None):
        """Save the landmark of the tick at ``stamp`` (s), the publisher's ``sample``
        (a core/landmark_format.SampleMark, if known); return ``(label, '')`` or ``('', why
        not)``. The first tick's start is the odometry at ``stamp - period`` (when the
        publisher started), or the first odometry seen if that is later. A sample
        the file holds already (caught up) is skipped."""
        with self._lock:
            if command not in COMMANDS:
                return self._refuse('unknown command %r (expected one of %s)'
                                    % (command, ', '.join(COMMANDS)))
            if self.finished:
                self._follow_mission()
            if self.finished:
                return self._refuse('recording has finished (a final sample was saved)')
            if self.writer.holds(sample):
                return '', 'sample %d is in the file already' % sample.seq
            if self.odometry.latest() is None:
                return self._refuse('no valid odometry received on %s yet'
                                    % rospy.resolve_name(names.ODOM))
            age = self.odometry.age()
            if age > self.params.odom_timeout and self.odometry.lost is None:
                self.log.warn_throttle(5.0, 'odometry on %s is %.1f s old',
                                       rospy.resolve_name(names.ODOM), age)
            if stamp > 0:
                odom = self.odometry.state_at(stamp, wait=self.params.odom_wait)
            else:                               # an unstamped request: the latest odometry
                odom = self.odometry.latest()
            if not self.recorder.started:
                valid = stamp > 0 and math.isfinite(period) and period > 0
                self._start_chain(self.odometry.state_at(stamp - period) if valid else odom)
            label, outcome = self._take(command, yaw, period, odom, sample)
        if not label:
            return '', outcome
        self._report(label, outcome)
        return label, ''

    def _start_chain(self, state):
        """Start the recorder's d chain at ``state`` (lock held)."""
        self.recorder.start(state)
        self._poses.extend((state.x, state.y, state.yaw))

    def _take(self, command, yaw, period, odom, sample):
        """Make the landmark of a sample at odometry ``odom`` and write it (lock
        held): ``(label, landmark)``, or ``('', why not)``."""
        try:
            landmark = self.recorder.take(odom, yaw, period)
        except ValueError as error:
            return self._refuse('bad %s sample: %s' % (command, error))
        try:
            label = self.writer.append(landmark, sample)
        except StorageError as error:
            return self._write_failed(error)
        self._poses.extend((odom.x, odom.y, odom.yaw))
        self.finished = command == FINAL
        if self.finished:
            try:
                self.writer.finish()
            except StorageError as error:
                self._write_failed(error)
            self.log.info('final landmark saved; recording finished')
        return label, landmark

    @property
    def resuming(self):
        """True if this saver continued the mission's file and may catch up."""
        return self.writer.resumed is not None and not self.finished

    def start_catch_up(self, subscribed):
        """Take the lock now and catch up in a thread, so samples that arrive meanwhile
        wait for it: call before subscribing to them. The thread asks for the record once
        ``subscribed()`` (connected to the publisher) or after ``catch_up_timeout``."""
        self._lock.acquire()

        def run():
            try:
                wait_wall(subscribed, self.params.catch_up_timeout, poll=0.01)
                self._catch_up()
            finally:
                self._lock.release()
        thread = threading.Thread(target=self.guard(run), name='catch_up')
        thread.daemon = True
        thread.start()
        return thread

    def _catch_up(self):
        """Ask the sampling publisher for the samples this file misses and save them
        (module docstring; the lock held); True if the chain was restored."""
        mark = self.writer.sample
        if mark is None and self.writer.count:
            self.log.warn('%s does not say which sample its last landmark came from: cannot '
                          'catch up; the recording goes on after a gap', self.writer.path)
            return False
        name = rospy.resolve_name(names.RECORDED_SAMPLES)
        try:
            rospy.wait_for_service(name, self.params.catch_up_timeout)
            answer = rospy.ServiceProxy(name, RecordedSamples)(
                recording=mark.recording if mark else 0.0, after=mark.seq if mark else 0)
        except (rospy.ROSException, rospy.ServiceException) as error:
            self.log.warn('cannot catch up on the samples missed (%s); the recording goes on '
                          'after a gap', error)
            return False
        problem = answer_problem(answer, mark)
        if problem:
            self.log.warn('cannot catch up on the samples missed: %s; the recording goes on '
                          'after a gap', problem)
            return False
        caught = []
        for index, sample in enumerate(answer.samples):
            state = OdomState(answer.x[index], answer.y[index], sample.yaw, answer.v[index],
                              answer.w[index], sample.header.stamp.to_sec())
            if index == 0:              # the file's last sample (or the start): the chain
                self.recorder = PathRecorder()
                self._start_chain(state)
                self.writer.chain_restored()
                continue
            if sample.command == START or self.finished:
                break
            label, landmark = self._take(sample.command, sample.yaw, sample.period, state,
                                         SampleMark(answer.recording, sample.seq))
            if label:
                caught.append((label, landmark))
        self.log.warn('caught up: %d landmark(s) of samples %d to %d saved from the sampling '
                      "publisher's record; no gap in %s", len(caught), answer.samples[0].seq + 1,
                      answer.samples[-1].seq, self.writer.path)
        if caught:
            self._report(*caught[-1])
        return True

    def _write_failed(self, error):
        """A landmark could not be written: ERROR, and the storage message says so."""
        self.error = str(error)
        landmark_lost(self.log, error)
        self._publish_storage(rospy.Time.now())
        return '', self.error

    def _on_reanchor(self, reason, trusted):
        """The odometry jumped and the gate took the new stream: carried across in the old
        frame (``trusted``: the chain goes on), or the d chain breaks here (a gap whose reason
        names the reset: the return refuses such a file, core/odometry_reset.is_untrusted_reset)."""
        if trusted:
            return
        with self._lock:
            if self.finished or not self.recorder.started:
                return
            latest = self.odometry.latest()
            if latest is not None:
                self.recorder.restart(latest)
            else:
                self.recorder = PathRecorder()
            try:
                note_gap(self.writer, reason, self.log)
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
            self.path_pub.publish(path_message(self._poses, now, self.odometry.frame_id))

    def _publish_storage(self, now):
        msg, used = storage_message(self.writer, self.error, now, self._check_space(now))
        self.storage_pub.publish(msg)
        return used

    def _check_space(self, now):
        """The low-space warning now (core/recorder.SpaceWatch), logged when it appears."""
        warning, appeared = self.space.update(now.to_sec(), self.writer.bytes, self.writer.count)
        if appeared:
            self.log.warn('%s', warning)
        return warning


def recording_status(stat, writer, error, space_warning, finished):
    """The recording's diagnostics: ``writer``'s file, its last ``error``, the free space's
    warning, whether the recording has ``finished``."""
    stat.add('file', writer.path)
    stat.add('landmarks', writer.count)
    stat.add('bytes', writer.bytes)
    stat.add('lost', writer.lost)
    if error:
        stat.summary(diagnostics.ERROR, '%d landmark(s) lost: %s' % (writer.lost, error))
    elif space_warning:
        stat.summary(diagnostics.WARN, space_warning)
    elif finished:
        stat.summary(diagnostics.OK, 'recording finished: %d landmarks' % writer.count)
    else:
        stat.summary(diagnostics.OK, 'recording: %d landmarks, %.2f m'
                     % (writer.count, writer.total_distance))


def storage_message(writer, error, stamp, space_warning=''):
    """(blind_navigation/StorageUsage, core/recorder storage_usage) of ``writer``'s file."""
    used = storage_usage(writer.count, writer.bytes, writer.total_distance)
    mark = writer.sample
    msg = StorageUsage(file=writer.path, landmarks=used.landmarks, bytes=used.bytes,
                       distance=used.distance, bytes_per_metre=used.bytes_per_metre,
                       lost=writer.lost, lost_distance=writer.lost_distance,
                       lost_turn=writer.lost_turn, error=error, space_warning=space_warning,
                       recording=mark.recording if mark else 0.0, sample=mark.seq if mark else 0)
    msg.header.stamp = stamp
    return msg, used


def path_message(poses, stamp, frame_id):
    """The nav_msgs/Path of ``poses`` (x, y, yaw, x, y, yaw, ...)."""
    path = Path()
    path.header.stamp, path.header.frame_id = stamp, frame_id
    for index in range(0, len(poses), 3):
        pose = PoseStamped(header=path.header)
        set_pose(pose.pose, *poses[index:index + 3])
        path.poses.append(pose)
    return path


def landmark_lost(log, error):
    """Log a landmark the file could not take (``error``), as an ERROR."""
    log.error('LANDMARK LOST: %s', error)


def note_gap(writer, reason, log):
    """Note an odometry gap (``reason``) in ``writer``'s file and log it (raises StorageError)."""
    gap = writer.note_gap(reason)
    log.error('odometry discontinuity: %s noted in %s; the next landmark counts from the new '
              'odometry', gap, writer.path)

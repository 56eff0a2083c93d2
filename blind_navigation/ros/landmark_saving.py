"""The paper's recorders (3.3.3, Figure 4): the landmark saver (topic), the record server
(service) and its client. A tick's landmark from the odometry at its stamp, appended to the
mission's file; ``storage``, ``recorded_path``; gaps, catch-up (docs/recording.md, "Saving").
"""
import math
import os
import threading
import time
from array import array

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path

from blind_navigation import names
from blind_navigation.core.geometry import OdomState
from blind_navigation.core.recorder import PathRecorder
from blind_navigation.core.sample_log import COMMANDS, FINAL, START, answer_problem
from blind_navigation.core.store import SampleMark
from blind_navigation.core.mission_files import open_mission_file
from blind_navigation.core.role_params import LANDMARK_SAVING
from blind_navigation.msg import PathSample, StorageUsage
from blind_navigation.srv import RecordedSamples, RecordLandmark, RecordLandmarkResponse
from blind_navigation.ros.common import ros_home_file, set_pose, subscribe
from blind_navigation.ros.mission import Role
from blind_navigation.ros.mission_store import FileStore

#: The landmark file when ``landmark_file`` is empty: under $ROS_HOME (default ~/.ros).
LANDMARK_FILE = os.path.join('blind_navigation', 'landmarks.yaml')


class LandmarkSaving(Role):
    """Odometry at a tick -> landmark -> mission file, storage and recorded path; ``VARIANT``:
    the recorder, in the file's metadata."""

    SCHEMA = LANDMARK_SAVING

    def __init__(self, layer):
        Role.__init__(self, layer)
        self.odometry = layer.odometry
        self.odometry.acquire(self.ROLE)   # reads back: at a stamp, waiting for it
        self.odometry.on_reanchor(self.guard(self._on_reanchor))
        self._lock = threading.Lock()
        self.writer = None
        self._open()
        rospy.on_shutdown(lambda: self.writer.close())
        self.storage_pub = rospy.Publisher(names.STORAGE, StorageUsage, queue_size=10)
        self.path_pub = rospy.Publisher(names.RECORDED_PATH, Path, queue_size=1, latch=True)
        self.follow('%s: recording' % self.ROLE)
        once = threading.Lock()     # ready: samples taken once the feed has a state

        def on_state(_state):
            if once.acquire(False):
                self.odometry.remove_listener(listener)
                self._take_samples()
        listener = self.guard(on_state)
        self.odometry.add_listener(listener)
        if self.odometry.latest() is not None:
            listener(None)
        else:
            self.log.warn('no odometry on %s yet: not taking samples until it comes',
                          rospy.resolve_name(names.ODOM))

    def _diagnose(self, stat):
        self.store.status(stat, self.finished)

    def _open(self):
        """Open the mission's file (continued within the mission, else a new one), the path
        started (lock held, or before the callbacks exist)."""
        self._poses = array('d')       # x, y, yaw of every landmark (and the start)
        self.recorder = PathRecorder()
        configured = ros_home_file(LANDMARK_FILE, self.params.landmark_file)
        self.mission_id = self.layer.current_mission_id()   # of the file open
        self.writer = open_mission_file(configured, self.mission_id, fsync=self.params.fsync, metadata={
            'recorder': self.VARIANT, 'odom_topic': rospy.resolve_name(names.ODOM),
            'started_ros_time': round(rospy.Time.now().to_sec(), 3)})
        self.store = FileStore(self.writer)
        self.finished = self.writer.finished   # a continued mission file may be finished already
        path = self.writer.path
        self.store.storage(rospy.Time.now())     # the free space checked
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
        """A new mission id (lock held): the old file closed, the new one opened, RViz's path
        emptied; at the new mission's state or first sample, whichever comes first."""
        if self.layer.current_mission_id() != self.mission_id:
            self.writer.close()
            self._open()
            self.path_pub.publish(path_message(self._poses, rospy.Time.now(), self.odometry.frame_id))

    def save(self, command, yaw, period, stamp, sample=None):
        """Save the landmark of the tick at ``stamp`` (``sample``: its SampleMark, if known):
        ``(label, '')`` or ``('', why not)``; the chain starts at the odometry at ``stamp - period``."""
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
        """Write the landmark of a sample at ``odom`` (lock held): ``(label, landmark)`` or ``('', why)``."""
        try:
            landmark = self.recorder.take(odom, yaw, period)
        except ValueError as error:
            return self._refuse('bad %s sample: %s' % (command, error))
        label = self.store.append(landmark, sample)
        if label is None:
            self._publish_storage(rospy.Time.now())
            return '', self.store.error
        self._poses.extend((odom.x, odom.y, odom.yaw))
        self.finished = command == FINAL
        if self.finished:
            self.store.finish()
            self.log.info('final landmark saved; recording finished')
        return label, landmark

    def _on_reanchor(self, reason, trusted):
        """A re-anchor: ``trusted`` (carried across) goes on, else the d chain breaks (a gap)."""
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
            self.store.note_gap(reason)

    def _refuse(self, reason):
        self.log.warn_throttle(2.0, 'landmark not saved: %s', reason)
        return '', reason

    def _report(self, label, landmark):
        """Publish (and log) the storage and, when listened to, the recorded path."""
        now = rospy.Time.now()
        used = self._publish_storage(now)
        self.log.info('%s %s: %d landmarks, %d bytes, %.2f m, %.0f B/m', label,
                      [round(value, 4) for value in landmark], used.landmarks, used.bytes,
                      used.distance, used.bytes_per_metre)
        if self.path_pub.get_num_connections() > 0 or self.finished:
            self.path_pub.publish(path_message(self._poses, now, self.odometry.frame_id))

    def _publish_storage(self, now):
        msg = self.store.storage(now)
        self.storage_pub.publish(msg)
        return msg


def path_message(poses, stamp, frame_id):
    """The nav_msgs/Path of ``poses`` (x, y, yaw, x, y, yaw, ...)."""
    path = Path()
    path.header.stamp, path.header.frame_id = stamp, frame_id
    for index in range(0, len(poses), 3):
        pose = PoseStamped(header=path.header)
        set_pose(pose.pose, *poses[index:index + 3])
        path.poses.append(pose)
    return path


class LandmarkSaver(LandmarkSaving):
    """The paper's subscriber: each sample is one landmark (restarted: caught up first)."""

    ROLE, VARIANT = 'landmark_saver', 'topic'
    sample_sub = None

    def _take_samples(self):
        """Subscribe to the samples; a continued file first catches up, the lock held until it
        asked (once subscribed, or after ``catch_up_timeout``) so that samples arriving wait."""
        if self.writer.resumed is not None and not self.finished:
            self._lock.acquire()
            threading.Thread(target=self.guard(self._catch_up), name='catch_up', daemon=True).start()
        self.sample_sub = subscribe(names.SAMPLE, PathSample, self.guard(self.on_sample), queue_size=20)

    def _catch_up(self):
        """Save the samples this file misses, asked of the publisher (lock held, then released)."""
        try:
            deadline = time.monotonic() + self.params.catch_up_timeout
            while (self.sample_sub is None or self.sample_sub.get_num_connections() == 0) \
                    and time.monotonic() < deadline and not rospy.is_shutdown():
                time.sleep(0.01)
            self._save_missed()
        finally:
            self._lock.release()

    def _save_missed(self):
        """The catch-up itself (lock held)."""
        mark = self.writer.sample
        if mark is None and self.writer.count:
            problem = '%s does not say which sample its last landmark came from' % self.writer.path
        else:
            try:
                rospy.wait_for_service(names.RECORDED_SAMPLES, self.params.catch_up_timeout)
                answer = rospy.ServiceProxy(names.RECORDED_SAMPLES, RecordedSamples)(
                    recording=mark.recording if mark else 0.0, after=mark.seq if mark else 0)
                problem = answer_problem(answer, mark)
            except (rospy.ROSException, rospy.ServiceException) as error:
                problem = str(error)
        if problem:
            self.log.warn('cannot catch up on the samples missed: %s; the recording goes on after a gap',
                          problem)
            return
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

    def on_sample(self, msg):
        self.save(msg.command, msg.yaw, msg.period, msg.header.stamp.to_sec(),
                  SampleMark(msg.recording, msg.seq) if msg.seq else None)


class RecordServer(LandmarkSaving):
    """The paper's service server: a ``record_landmark`` request is one landmark."""

    ROLE, VARIANT = 'record_server', 'service'
    service = None

    def _take_samples(self):
        self.service = rospy.Service(names.RECORD_LANDMARK, RecordLandmark,
                                     self.guard(self.on_request))

    def on_request(self, request):
        label, why_not = self.save(request.command, request.yaw, request.period,
                                   request.header.stamp.to_sec())
        return RecordLandmarkResponse(saved=bool(label), label=label, message=why_not)


class RecordClient(Role):
    """The paper's service client: each sample a ``record_landmark`` request, once it is served."""

    ROLE = 'record_client'

    def __init__(self, layer):
        Role.__init__(self, layer)
        self.calls = 0
        self.service = rospy.resolve_name(names.RECORD_LANDMARK)
        self.record = rospy.ServiceProxy(names.RECORD_LANDMARK, RecordLandmark, persistent=False)
        self.sample_sub = None

    def run(self):
        """Block until the server is up (or shutdown); then subscribe to the samples."""
        self.log.info('waiting for %s', self.service)
        try:
            rospy.wait_for_service(names.RECORD_LANDMARK)
        except rospy.ROSInterruptException:
            return
        self.log.info('%s is up; forwarding %s', self.service, rospy.resolve_name(names.SAMPLE))
        self.sample_sub = subscribe(names.SAMPLE, PathSample, self.guard(self.on_sample),
                                    queue_size=20)

    def on_sample(self, msg):
        self.calls += 1
        try:
            response = self.record(header=msg.header, command=msg.command, yaw=msg.yaw,
                                   period=msg.period)
        except (rospy.ServiceException, rospy.ROSException) as error:
            self.log.error('%s call %d failed: %s', self.service, self.calls, error)
            return
        if not response.saved:
            self.log.warn('server did not save the %s sample: %s', msg.command, response.message)

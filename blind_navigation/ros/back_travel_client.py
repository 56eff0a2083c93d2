"""back_travel_client: the paper's action client (section 3.3.7, Figure 6) and
the sole owner of the mission state.

State walk, published latched on /blind_navigation/state (std_msgs/String):
``idle`` -> ``recording`` (first /blind_navigation/storage seen) ->
``rotating`` (/blind_navigation/vision_lost) -> ``returning``
(/blind_navigation/rotation_done true) -> ``home`` (every goal succeeded) or
``aborted`` (with the reason logged: rotation failed, bad landmark file, no
server, a goal failed, a Kobuki safety event, a time allowance exceeded).

At vision loss it takes the anchor (odometry position where recording
stopped) and the landmark file's real path (``landmark_file`` is the
recorder's symlink). When returning: loads that file with
core/store.load_landmarks (a bad file aborts with the file and entry named;
nothing is driven), waits for the /blind_navigation/back_travel server
(``server_timeout``), sets the route (/blind_navigation/set_return_route), then
sends the landmarks in reverse order, one goal at a time, each within its
allowance and the whole return within ``return_timeout_factor`` x the expected
time + ``return_timeout_margin``. Publishes the odometry poses of the return on
/blind_navigation/return_path.

Gyro heading correction (docs/back_travel.md): with ``heading_correction``
true, ``odom_topic`` is heading_correction's corrected odometry, and the
landmarks are expressed in its frame before they are sent
(core/heading_correction.correct_landmarks with the latched
/blind_navigation/heading_correction, awaited at most ``correction_timeout``
when the return starts; none: aborted, as the frames would not agree). The
landmark file itself is not changed.

Progress (core/safety.ReturnProgress: real path and sha256 of the landmark
file, anchor, landmarks completed, position) is written atomically to
``<landmark_file stem>.progress.yaml`` next to ``landmark_file`` at vision loss
and after each goal. A client restarted while a return was under way
(progress ``returning``, updated within ``resume_timeout`` wall seconds, file
unchanged, robot within ``resume_max_offset`` of where it stopped) resumes
with the next landmark instead of starting over; otherwise it aborts or, for a
finished or old return, starts ``idle``. The landmark file is only read.
"""
import os
import threading
import time

import actionlib
import rospy
from actionlib.action_client import get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from std_msgs.msg import Bool, Empty, String

from blind_navigation import names
from blind_navigation.ros.back_travel_common import (LatestOdom, SafetyMonitor, landmarks_in_corrected_frame)
from blind_navigation.core import mission_state as state
from blind_navigation.core.geometry import distance, quaternion_from_yaw
from blind_navigation.core.landmark import KOBUKI_MAX_V, KOBUKI_MAX_W, Limits
from blind_navigation.core.safety import (SAFETY_DEFAULTS, ProgressError, ReturnProgress,
                                          expected_duration, file_digest, load_progress,
                                          position_check, progress_path, resume_check,
                                          return_allowance, save_progress)
from blind_navigation.core.store import LandmarkFileError, load_landmarks
from blind_navigation.msg import BackTravelAction, BackTravelGoal, StorageUsage
from blind_navigation.msg import HeadingCorrection as HeadingCorrectionMsg
from blind_navigation.ros.common import load_params
from blind_navigation.srv import SetReturnRoute

#: How often the goal wait checks safety events and allowances, s.
WAIT_SLICE = 0.02


class BackTravelClient(object):
    """Mission state machine and goal sender.

    Params (DEFAULTS): ``landmark_file``
    ('~/.ros/blind_navigation/landmarks.yaml', the recorder's symlink),
    ``odom_topic`` ('/odom': anchor, progress, return_path), ``odom_timeout``
    (s, 0.5: odometry older than this is not used for the anchor),
    ``server_timeout`` (s, 10: wait for the action server),
    ``goal_timeout_factor`` (5) and ``goal_timeout_margin`` (s, 10): a goal's
    result is awaited at most factor * max(T, d / max(|v|, slowest_v)) + margin
    (a backstop: the server's own allowance is tighter),
    ``return_timeout_factor`` (3) and ``return_timeout_margin`` (s, 30): the
    whole return's allowance, ``slowest_v`` (m/s, 0.03), ``max_v`` / ``max_w``
    (0.7 m/s, pi rad/s, Kobuki's limits: a landmark beyond them is a bad
    file), ``resume_timeout`` (s wall, 600) and ``resume_max_offset`` (m, 0.5):
    when a restarted client resumes, ``path_spacing`` (m, 0.02 between
    return_path poses), ``heading_correction`` (false: landmarks as recorded;
    true: in the frame of /blind_navigation/heading_correction),
    ``correction_timeout`` (s, 5), ``bumper_topic`` / ``cliff_topic`` /
    ``wheel_drop_topic``.
    """

    DEFAULTS = dict({
        'landmark_file': os.path.join('~', '.ros', 'blind_navigation', 'landmarks.yaml'),
        'odom_topic': '/odom',
        'odom_timeout': 0.5,
        'server_timeout': 10.0,
        'goal_timeout_factor': 5.0,
        'goal_timeout_margin': 10.0,
        'return_timeout_factor': 3.0,
        'return_timeout_margin': 30.0,
        'slowest_v': SAFETY_DEFAULTS['slowest_v'],
        'max_v': KOBUKI_MAX_V,
        'max_w': KOBUKI_MAX_W,
        'resume_timeout': SAFETY_DEFAULTS['resume_timeout'],
        'resume_max_offset': SAFETY_DEFAULTS['resume_max_offset'],
        'path_spacing': 0.02,
        'heading_correction': False,
        'correction_timeout': 5.0,
    }, **{kind + '_topic': topic for kind, topic in names.SAFETY_EVENTS.items()})

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        if not isinstance(p.landmark_file, str) or not p.landmark_file.strip():
            raise ValueError('~landmark_file must be a file path, got %r' % (p.landmark_file,))
        for name in ('odom_timeout', 'server_timeout', 'goal_timeout_factor', 'return_timeout_factor',
                     'slowest_v', 'max_v', 'max_w', 'resume_timeout', 'resume_max_offset',
                     'path_spacing', 'correction_timeout'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        self.limits = Limits(p.max_v, p.max_w)
        self.progress_file = progress_path(p.landmark_file)
        self.progress = None
        self.state = None
        self._lock = threading.Lock()
        self._return = threading.Event()
        self._trip = None
        self.correction = None
        self.state_pub = rospy.Publisher(names.STATE, String, queue_size=1, latch=True)
        self.path_pub = rospy.Publisher(names.RETURN_PATH, Path, queue_size=1, latch=True)
        self.path = Path()
        # Made when the return starts, not here: rospy drops a publisherUpdate that
        # arrives while registerSubscriber is in flight (RegManager keeps only the
        # newest update per topic, the call's stale empty list), so subscribing at
        # start-up, while the server registers, can leave feedback/result unconnected
        # for good ("action server not available"). By the return the server is known.
        self.client = None
        self._start_from_progress()
        self.odom = LatestOdom(p.odom_topic, self._on_odom)
        self.safety = SafetyMonitor({kind: getattr(p, kind + '_topic') for kind in names.SAFETY_EVENTS},
                                    self._on_trip)
        rospy.Subscriber(names.STORAGE, StorageUsage, self._on_storage, queue_size=5)
        rospy.Subscriber(names.VISION_LOST, Empty, self._on_vision_lost, queue_size=1)
        rospy.Subscriber(names.ROTATION_DONE, Bool, self._on_rotation_done, queue_size=1)
        if p.heading_correction:
            rospy.Subscriber(names.HEADING_CORRECTION, HeadingCorrectionMsg, self._on_correction,
                             queue_size=1)
        rospy.on_shutdown(self._on_shutdown)

    # --- state ---------------------------------------------------------------

    def set_state(self, new_state, reason=''):
        with self._lock:
            old, self.state = self.state, new_state
        if self.progress is not None and new_state in (state.HOME, state.ABORTED):
            self._save_progress(status=new_state)   # persisted before it is announced
        log = rospy.logerr if new_state == state.ABORTED else rospy.loginfo
        log('%s: state %s -> %s%s', rospy.get_name(), old, new_state, ': ' + reason if reason else '')
        self.state_pub.publish(String(data=new_state))

    def _transition(self, expected, new_state, event):
        """Move to ``new_state`` if the state is ``expected``; log and ignore otherwise."""
        with self._lock:
            current = self.state
        if current != expected:
            if event != 'storage':
                rospy.logwarn('%s: %s ignored in state %s', rospy.get_name(), event, current)
            return False
        self.set_state(new_state)
        return True

    def _start_from_progress(self):
        """First state: ``returning`` to resume an unfinished return, ``aborted``
        if one was under way but cannot continue, else ``idle``."""
        try:
            progress = load_progress(self.progress_file)
        except ProgressError as error:
            rospy.logerr('%s: %s; not resuming anything', rospy.get_name(), error)
            progress = None
        if progress is None:
            self.set_state(state.IDLE)
            return
        try:
            digest = file_digest(progress.landmark_file)
        except OSError:
            digest = None
        decision, why = resume_check(progress, time.time(), digest, self.params.resume_timeout)
        if decision == 'ignore':
            rospy.loginfo('%s: %s (%s)', rospy.get_name(), why, self.progress_file)
            self.set_state(state.IDLE)
            return
        self.progress = progress
        if decision == 'abort':
            self.set_state(state.ABORTED, why)
            return
        rospy.logwarn('%s: %s (%s)', rospy.get_name(), why, self.progress_file)
        self.set_state(state.RETURNING, 'resume after a restart')
        self._return.set()

    def _save_progress(self, **changes):
        """Update and persist the progress (atomically, next to the landmark file)."""
        odom = self.odom.fresh(self.params.odom_timeout) if hasattr(self, 'odom') else None
        if odom is not None:
            changes.setdefault('position', [odom.x, odom.y])
        self.progress = self.progress._replace(updated=time.time(), **changes)
        try:
            save_progress(self.progress_file, self.progress)
        except OSError as error:
            rospy.logerr('%s: cannot write the return progress %s: %s', rospy.get_name(),
                         self.progress_file, error)

    # --- events --------------------------------------------------------------

    def _on_storage(self, _msg):
        self._transition(state.IDLE, state.RECORDING, 'storage')

    def _on_vision_lost(self, _msg):
        if self._transition(state.RECORDING, state.ROTATING, 'vision_lost'):
            odom = self.odom.fresh(self.params.odom_timeout)
            anchor = [odom.x, odom.y] if odom else None
            self.progress = ReturnProgress(
                landmark_file=os.path.realpath(os.path.expanduser(self.params.landmark_file)),
                digest='', landmarks=0, anchor=anchor, frame_id=self.odom.frame_id, completed=0,
                position=anchor, status=state.ROTATING, updated=time.time())
            self._save_progress()

    def _on_rotation_done(self, msg):
        if not msg.data:
            safety = self._trip or ', '.join(self.safety.active)
            reason = 'the pi rotation failed%s; not travelling back' % (
                ' (safety stop: %s)' % safety if safety else '')
            with self._lock:
                rotating = self.state == state.ROTATING
            if rotating:
                self.set_state(state.ABORTED, reason)
            return
        if self._transition(state.ROTATING, state.RETURNING, 'rotation_done true'):
            self._return.set()

    def _on_correction(self, msg):
        self.correction = msg

    def _wait_for_correction(self):
        """The latched heading correction (wall-bounded wait), or None."""
        deadline = time.monotonic() + self.params.correction_timeout
        while self.correction is None and time.monotonic() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)
        return self.correction

    def _in_corrected_frame(self, landmarks):
        """``landmarks`` in the corrected odometry frame; (landmarks, problem)."""
        if not self.params.heading_correction:
            return landmarks, None
        msg = self._wait_for_correction()
        if msg is None:
            return None, ('no heading correction on %s within %.0f s (is heading_correction '
                          'running?)' % (names.HEADING_CORRECTION, self.params.correction_timeout))
        corrected, correction = landmarks_in_corrected_frame(landmarks, msg)
        rospy.loginfo('%s: landmarks in the corrected odometry frame: %s', rospy.get_name(),
                      correction.describe())
        return corrected, None

    def _on_trip(self, reason):
        if self.state in (state.ROTATING, state.RETURNING):
            self._trip = reason

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
        if self.state == state.RETURNING and self.client is not None:
            self.client.cancel_all_goals()

    # --- the return ------------------------------------------------------------

    def spin(self):
        while not rospy.is_shutdown():
            if self._return.wait(0.2):
                self._return.clear()
                ok, reason = self.travel_back()
                if not rospy.is_shutdown():
                    self.set_state(state.HOME if ok else state.ABORTED, reason)

    def travel_back(self):
        """Figure 6: load, reverse, send goal by goal (from the first landmark not
        completed yet). Returns (ok, reason)."""
        p = self.params
        resuming = self.progress.status == state.RETURNING
        path = self.progress.landmark_file
        try:
            loaded = load_landmarks(path, limits=self.limits)
            digest = file_digest(path)
        except OSError as error:
            return False, 'landmark file unusable: %s: cannot read: %s' % (path, error.strerror)
        except LandmarkFileError as error:
            return False, 'landmark file unusable: %s' % error
        for warning in loaded.warnings:
            rospy.logwarn('%s: %s', rospy.get_name(), warning)
        landmarks, problem = self._in_corrected_frame(loaded.landmarks)
        if problem:
            return False, problem
        goals = list(zip(loaded.labels, landmarks))[::-1]
        if resuming:
            if digest != self.progress.digest or len(goals) != self.progress.landmarks:
                return False, 'landmark file %s changed since the return started' % path
            problem = self._wait_for_position()
            if problem:
                return False, 'cannot resume: %s' % problem
        elif self.progress.anchor is None:
            odom = self.odom.fresh(p.odom_timeout)
            if odom is None:
                return False, 'no odometry for the return: %s' % self.odom.describe_missing(
                    p.odom_timeout)
            self.progress = self.progress._replace(anchor=[odom.x, odom.y])
        done = self.progress.completed if resuming else 0
        self._save_progress(status=state.RETURNING, digest=digest, landmarks=len(goals),
                            completed=done)
        rospy.loginfo('%s: %d landmarks, %.2f m, from %s; %s; waiting for %s', rospy.get_name(),
                      len(goals), loaded.total_distance, path,
                      'resuming after %d' % done if done else 'starting', names.BACK_TRAVEL)
        if self.client is None:
            self.client = actionlib.SimpleActionClient(names.BACK_TRAVEL, BackTravelAction)
        if not self.client.wait_for_server(rospy.Duration(p.server_timeout)):
            return False, ('action server %s not available after %.0f s (is back_travel_server '
                           'running?)' % (names.BACK_TRAVEL, p.server_timeout))
        problem = self._set_route([landmark for _, landmark in goals[:done]])
        if problem:
            return False, problem
        remaining = [landmark for _, landmark in goals[done:]]
        allowance = return_allowance(remaining, p.return_timeout_factor, p.return_timeout_margin,
                                     p.slowest_v)
        deadline = rospy.get_time() + allowance
        travelled = 0.0
        for number, (label, landmark) in enumerate(goals[done:], done + 1):
            where = 'goal %d/%d (%s)' % (number, len(goals), label)
            self.client.send_goal(BackTravelGoal(*landmark.as_list()))
            problem = self._wait_for_goal(where, landmark, deadline, allowance)
            if problem:
                return False, problem
            status = self.client.get_state()
            if status != GoalStatus.SUCCEEDED:
                return False, '%s ended %s: %s' % (where, get_name_of_constant(GoalStatus, status),
                                                    self.client.get_goal_status_text())
            travelled += self.client.get_result().distance
            self._save_progress(completed=number)
        return True, 'travelled %.3f m over %d landmarks%s' % (
            travelled, len(goals) - done, ' (resumed after %d)' % done if done else '')

    def _wait_for_position(self):
        """Resuming: wait (wall-bounded) for odometry, check the robot is where the
        return stopped; None if fine, else why not."""
        deadline = time.monotonic() + self.params.server_timeout
        odom = None
        while odom is None and time.monotonic() < deadline and not rospy.is_shutdown():
            odom = self.odom.fresh(self.params.odom_timeout)
            time.sleep(0.05)
        return position_check(self.progress, [odom.x, odom.y] if odom else None,
                              self.params.resume_max_offset)

    def _set_route(self, completed):
        """Give the server the route: anchor + completed landmarks. None if set."""
        request_timeout = self.params.server_timeout
        try:
            rospy.wait_for_service(names.SET_RETURN_ROUTE, request_timeout)
            set_route = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
            response = set_route(header=rospy.Header(stamp=rospy.Time.now(),
                                                     frame_id=self.progress.frame_id or ''),
                                 anchor_x=self.progress.anchor[0], anchor_y=self.progress.anchor[1],
                                 completed=[value for lm in completed for value in lm.as_list()])
        except (rospy.ROSException, rospy.ServiceException) as error:
            return 'cannot set the return route on %s: %s' % (names.SET_RETURN_ROUTE, error)
        return None if response.ok else 'return route refused: %s' % response.message

    def _wait_for_goal(self, where, landmark, deadline, allowance):
        """Wait for the goal's result; cancel it and say why on a safety event, the
        goal's backstop or the whole return's allowance. None once it ended."""
        p = self.params
        goal_allowance = (p.goal_timeout_factor * expected_duration(landmark, p.slowest_v)
                          + p.goal_timeout_margin)
        goal_deadline = rospy.get_time() + goal_allowance
        while not self.client.wait_for_result(rospy.Duration(WAIT_SLICE)):
            now = rospy.get_time()
            if self._trip:
                problem = '%s: safety stop: %s' % (where, self._trip)
            elif now > goal_deadline:
                problem = '%s: no result within %.0f s' % (where, goal_allowance)
            elif now > deadline:
                problem = '%s: the return exceeded its time allowance of %.0f s' % (where, allowance)
            elif rospy.is_shutdown():
                problem = '%s: node shutting down' % where
            else:
                continue
            self.client.cancel_goal()
            return problem
        return None

"""The back-travel client: the paper's action client (section 3.3.7, Figure 6)
and the owner of the mission's state (core/mission_state.py).

It publishes the state latched on ``blind_navigation/state`` (std_msgs/String)
and, with its reason and the return's progress, on ``blind_navigation/status``
(blind_navigation/MissionStatus). Vision lost while recording: ``rotating``
(the anchor and the landmark file's real path kept); the pi turn reported done
(``blind_navigation/rotation_done``) and the robot really turned: it loads the
landmarks (core/store), expresses them in the heading-corrected frame, builds
the route (core/route; with ``prune_loops`` pruned by core/pruning), sets it on
the server (``blind_navigation/set_return_route``) and sends the landmarks in
reverse order, one goal at a time, within the whole return's allowance; then
``home`` or ``aborted`` with the reason. It publishes the return's poses on
``blind_navigation/return_path``. The progress (core/progress) is written next
to ``landmark_file`` at vision loss and after each goal: a restarted client
resumes or aborts. The landmark file is only read. A fault of this process
(ros/wiring.py: a refused topic, a role's exception) or one another process
reports on ``blind_navigation/role_failure`` ends the mission ``aborted``.
Transitions and reasons: docs/safety.md, "One state machine"; the return: docs/back_travel.md.
"""
import json
import math
import os
import threading
import time

import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Path
from std_msgs.msg import Bool, Empty, String

from blind_navigation import names
from blind_navigation.core import mission_state as state
from blind_navigation.core.geometry import distance, quaternion_from_yaw, wrap_angle
from blind_navigation.core.allowance import ALLOWANCE_DEFAULTS
from blind_navigation.core.gyro_bias import STANDSTILL_DEFAULTS, standstill_timeout
from blind_navigation.core.heading_correction import correct_landmarks
from blind_navigation.core.landmark import KOBUKI_MAX_V, KOBUKI_MAX_W, Limits
from blind_navigation.core.odometry_reset import is_untrusted_reset
from blind_navigation.core.plausibility import RouteBudget
from blind_navigation.core.pruning import PRUNE_DEFAULTS, prune_params, prune_route
from blind_navigation.core.route import ROUTE_DEFAULTS, Route, build_route
from blind_navigation.core.progress import (ABORT, IGNORE, PROGRESS_DEFAULTS, ProgressError,
                                            ReturnProgress, file_digest, progress_path,
                                            resume_from_file, save_progress, settle_abort)
from blind_navigation.core.safety import SAFETY_DEFAULTS, expected_duration, return_allowance
from blind_navigation.core.store import LandmarkFileError, load_landmarks
from blind_navigation.msg import BackTravelAction, BackTravelGoal, MissionStatus, StorageUsage
from blind_navigation.ros import diagnostics, wiring
from blind_navigation.ros.common import REQUIRED, shutting_down, subscribe
from blind_navigation.ros.goal_runner import GoalRunner
from blind_navigation.ros.landmark_saving import landmark_file
from blind_navigation.srv import SetReturnRoute

#: How often the goal wait checks safety events and allowances, s.
WAIT_SLICE = 0.02


class BackTravelClient(object):
    """Mission state machine and goal sender (module docstring)."""

    ROLE = 'back_travel_client'
    DEFAULTS = dict(ROUTE_DEFAULTS, **PRUNE_DEFAULTS, **{
        'landmark_file': '',            # the recorder's symlink (empty: under $ROS_HOME); only read
        'odom_timeout': 0.5,            # s; older odometry counts as missing
        'server_timeout': 10.0,         # s to wait for the back-travel server
        'goal_timeout_factor': 5.0,     # a goal may go factor x its expected time ...
        'goal_timeout_margin': 10.0,    # ... + margin, s without a result or feedback (a backstop
                                        # for a silent server; a driving one reports feedback)
        'return_timeout_factor': ALLOWANCE_DEFAULTS['return_timeout_factor'],
        'return_timeout_margin': ALLOWANCE_DEFAULTS['return_timeout_margin'],
        'slowest_v': SAFETY_DEFAULTS['slowest_v'],
        'max_v': KOBUKI_MAX_V,          # m/s; a landmark faster than this is a bad file
        'max_w': KOBUKI_MAX_W,          # rad/s; a landmark turning faster is a bad file
        'resume_timeout': PROGRESS_DEFAULTS['resume_timeout'],
        'resume_max_offset': PROGRESS_DEFAULTS['resume_max_offset'],
        'path_spacing': 0.02,           # m between the poses of return_path
        'heading_correction': REQUIRED,  # true: the landmarks in the heading-corrected frame
        'correction_timeout': 5.0,      # s the return waits for the heading correction (none: aborted)
        'standstill_time': STANDSTILL_DEFAULTS['standstill_time'],
        'rotation_margin': 60.0,        # s added to the standstill's timeout: the rotation_timeout,
                                        # from vision loss to the end of the pi turn
        'turn_tolerance': 0.3,          # rad a finished pi turn may differ from pi
        'prune_loops': REQUIRED,        # true: cut loops from the route (core/pruning; closed_loop)
    })

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.DEFAULTS, shared=('standstill_time',))
        self.log = layer.logger(self.ROLE)
        for name in ('odom_timeout', 'server_timeout', 'goal_timeout_factor', 'return_timeout_factor',
                     'slowest_v', 'max_v', 'max_w', 'resume_timeout', 'resume_max_offset',
                     'path_spacing', 'correction_timeout', 'rotation_margin', 'turn_tolerance'):
            if not getattr(p, name) > 0:
                raise ValueError('~%s must be positive, got %r' % (name, getattr(p, name)))
        if not isinstance(p.prune_loops, bool):
            raise ValueError('~prune_loops must be true or false, got %r' % (p.prune_loops,))
        prune_params(p)                  # a bad pruning param fails now, not at the return
        self.layer = layer
        self.odometry = layer.odometry
        self.landmark_file = landmark_file(p.landmark_file)
        self.rotation_timeout = standstill_timeout(p) + p.rotation_margin
        self.limits = Limits(p.max_v, p.max_w)
        self.progress_file = progress_path(self.landmark_file)
        self.progress = None
        self.state = None
        self.reason = ''
        self.warnings = ''
        self._losses = {}                # real path of a landmark file -> its last storage with a loss
        self._lock = threading.Lock()
        self._return = threading.Event()
        self._trip = None
        self._lost = None           # an untrusted odometry reset during the turn or the return
        self._turn_start = None          # raw odometry yaw where recording stopped
        self.correction = layer.heading_correction() if p.heading_correction else None
        self.state_pub = rospy.Publisher(names.STATE, String, queue_size=1, latch=True)
        self.status_pub = rospy.Publisher(names.STATUS, MissionStatus, queue_size=1, latch=True)
        self.path_pub = rospy.Publisher(names.RETURN_PATH, Path, queue_size=1, latch=True)
        self.route_pub = rospy.Publisher(names.RETURN_ROUTE, Path, queue_size=1, latch=True)
        self.path = Path()
        # Made when the return starts, not here: rospy drops a publisherUpdate that
        # arrives while registerSubscriber is in flight, so subscribing at start-up,
        # while the server registers, can leave feedback/result unconnected for good.
        self.client = None
        guard = self.guard = layer.guard(self.ROLE)
        self._start_from_progress()
        layer.safety.on_trip(guard(self._on_trip))
        wiring.on_fault(self._on_fault)
        self.odometry.on_reanchor(guard(self._on_reset))
        subscribe(names.ROLE_FAILURE, String, guard(self._on_failure_report), queue_size=10)
        subscribe(names.STORAGE, StorageUsage, guard(self._on_storage), queue_size=5)
        subscribe(names.VISION_LOST, Empty, guard(self._on_vision_lost), queue_size=1)
        subscribe(names.ROTATION_DONE, Bool, guard(self._on_rotation_done), queue_size=1)
        layer.diagnostics.add('mission', self._mission_status)
        layer.diagnostics.add('odometry', self._odometry_status)
        layer.diagnostics.add('landmark file', self._file_status)
        rospy.on_shutdown(self._on_shutdown)

    # --- state ---------------------------------------------------------------------------------
    def set_state(self, new_state, reason=''):
        with self._lock:
            old, self.state = self.state, new_state
            self.reason = reason
        if self.progress is not None and self.progress.unfinished and new_state in state.TERMINAL:
            self._save_progress(self.progress.finish(new_state, reason, time.time(),
                                                     self._position()))  # before it is announced
        (self.log.error if new_state == state.ABORTED else self.log.info)(
            'state %s -> %s%s', old, new_state, ': ' + reason if reason else '')
        self.layer.mission.set_local(new_state)
        self.state_pub.publish(String(data=new_state))
        self._publish_status()
        if new_state in (state.RECORDING, state.ROTATING, state.RETURNING):
            # while recording it only reads the odometry where vision is lost (catch_up)
            self.odometry.acquire(self.ROLE, batched=new_state == state.RECORDING)
        elif new_state in state.TERMINAL:
            self.odometry.release(self.ROLE)
        self.layer.diagnostics.now()

    def _publish_status(self):
        msg = MissionStatus(state=self.state or '', reason=self.reason, warnings=self.warnings,
                            landmarks=self.progress.landmarks if self.progress else 0,
                            completed=self.progress.completed if self.progress else 0)
        msg.header.stamp = rospy.Time.now()
        self.status_pub.publish(msg)

    def _transition(self, expected, new_state, event):
        """Move to ``new_state`` if the state is ``expected``; log and ignore otherwise."""
        with self._lock:
            current = self.state
        if current != expected:
            if event != 'storage':
                self.log.warn('%s ignored in state %s', event, current)
            return False
        self.set_state(new_state)
        return True

    def _start_from_progress(self):
        """First state: ``returning`` to resume an unfinished return of this mission,
        ``aborted`` if one was under way but cannot continue (or its progress
        cannot be trusted), else ``idle`` (core/progress.resume_from_file)."""
        p = self.params
        if not os.path.lexists(self.progress_file):
            self.set_state(state.IDLE)
            return
        position = self._wait_for_position()
        decision = resume_from_file(self.progress_file, time.time(), position,
                                    self.layer.mission_id, p.resume_timeout, p.resume_max_offset,
                                    self.limits)
        if decision.action == IGNORE:
            self.log.info('%s', decision.reason)
            self.set_state(state.IDLE)
            return
        if decision.action == ABORT:
            try:
                settle_abort(self.progress_file, decision, time.time())
            except (OSError, ProgressError) as error:
                self.log.error('cannot record the abort in %s: %s', self.progress_file, error)
            self.set_state(state.ABORTED, decision.reason)
            return
        self.progress = decision.progress
        self.log.warn('%s (%s)', decision.reason, self.progress_file)
        self.set_state(state.RETURNING, 'resume after a restart')
        self._return.set()

    def _position(self):
        odom = self.odometry.wait_fresh(self.params.odom_timeout)
        return [odom.x, odom.y] if odom is not None else None

    def _save_progress(self, progress):
        """Keep and persist ``progress`` (atomically, next to the landmark file)."""
        self.progress = progress
        try:
            save_progress(self.progress_file, progress)
        except (OSError, ProgressError) as error:
            self.log.error('cannot write the return progress %s: %s', self.progress_file, error)

    # --- events --------------------------------------------------------------------------------
    def _on_storage(self, msg):
        if msg.lost:
            self._losses[os.path.realpath(msg.file)] = msg
        if msg.lost or msg.error:
            warning = 'RECORDING DAMAGED: %d landmark(s) could not be written to %s: %s' % (
                msg.lost, msg.file, msg.error)
            if warning != self.warnings:
                self.warnings = warning
                self.log.error('%s', warning)
                self._publish_status()
                self.layer.diagnostics.now()
        self._transition(state.IDLE, state.RECORDING, 'storage')

    def _on_vision_lost(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        with self._lock:
            current = self.state
        if current != state.RECORDING:
            if current not in (state.ROTATING, state.RETURNING):   # repeats are simply idempotent
                self.log.warn('vision_lost from %s ignored in state %s', sender, current)
            return
        if self.odometry.lost:
            self.set_state(state.ABORTED, 'vision lost (%s), but %s: the way back is unknown; '
                           'not travelling back' % (sender, self.odometry.lost))
            return
        self.odometry.catch_up()
        latest = self.odometry.latest()
        anchor = [latest.x, latest.y] if latest is not None else None
        self._turn_start = latest.yaw if latest is not None else None
        self._save_progress(ReturnProgress.begin(self.landmark_file, anchor, self.odometry.frame_id,
                                                 time.time(), self.layer.mission_id))
        self.set_state(state.ROTATING, 'vision lost (%s)' % sender)
        rospy.Timer(rospy.Duration(self.rotation_timeout), self.guard(self._check_rotation),
                    oneshot=True)

    def _check_rotation(self, _event):
        if self.state == state.ROTATING:
            self.set_state(state.ABORTED, 'no finished pi turn within %.0f s of vision loss (is '
                           'rotate_pi running?)' % self.rotation_timeout)

    def _on_rotation_done(self, msg):
        with self._lock:
            rotating = self.state == state.ROTATING
        if not rotating:
            return
        lost = self._lost or self.odometry.lost
        if lost:
            self.set_state(state.ABORTED, 'the pi rotation: %s; not travelling back' % lost)
            return
        if not msg.data:
            safety = self._trip or ', '.join(self.layer.safety.active)
            self.set_state(state.ABORTED, 'the pi rotation failed%s; not travelling back' % (
                ' (safety stop: %s)' % safety if safety else ''))
            return
        problem = self._turn_problem()
        if problem:
            self.log.error('rotation_done true refused: %s', problem)
            return
        if self._transition(state.ROTATING, state.RETURNING, 'rotation_done true'):
            self._return.set()

    def _turn_problem(self):
        """Why the robot has not really turned by pi since recording stopped, or None."""
        latest = self.odometry.latest()
        if self._turn_start is None or latest is None:
            return None if latest is not None else 'no odometry to check the turn'
        turned = abs(wrap_angle(latest.yaw - self._turn_start))
        if abs(turned - math.pi) > self.params.turn_tolerance:
            return 'the robot turned %.2f rad since vision loss, not pi' % turned
        return None

    def _on_fault(self, reason):
        """A fault of this process (ros/wiring.py: a refused topic, a role's exception,
        ros/faults.py) or of another (``blind_navigation/role_failure``): the mission
        ends ``aborted`` with ``reason``."""
        with self._lock:
            current = self.state
        if current in state.TERMINAL:
            self.log.error('%s (the mission had ended %s)', reason, current)
            return
        self.set_state(state.ABORTED, reason)

    def _on_failure_report(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        if sender != rospy.get_name():          # this process's roles report at once
            self._on_fault('%s (%s)' % (msg.data, sender))

    def _on_trip(self, reason):
        if self.state in (state.ROTATING, state.RETURNING):
            self._trip = reason

    def _on_reset(self, reason, trusted):
        """An untrusted odometry reset: the frame of the turn and the route is lost
        (the feed is never fresh again: the server and rotate_pi hold)."""
        if not trusted and self.state in (state.ROTATING, state.RETURNING):
            self._lost = reason

    def _on_odom(self, raw):
        if self.state != state.RETURNING:
            return
        odom = self.odometry.fresh(self.params.odom_timeout)
        if odom is None:
            return
        poses = self.path.poses
        if poses and distance(poses[-1].pose.position.x, poses[-1].pose.position.y,
                              odom.x, odom.y) < self.params.path_spacing:
            return
        pose = PoseStamped()
        pose.header.stamp = rospy.Time.from_sec(raw.stamp)
        pose.header.frame_id = self.odometry.frame_id
        pose.pose.position.x, pose.pose.position.y = odom.x, odom.y
        q = pose.pose.orientation
        q.x, q.y, q.z, q.w = quaternion_from_yaw(odom.yaw)
        poses.append(pose)
        self.path.header = pose.header
        self.path_pub.publish(self.path)

    def _on_shutdown(self):
        if self.state == state.RETURNING and self.client is not None:
            self.client.cancel()

    # --- the return ----------------------------------------------------------------------------
    def run(self):
        """Drive returns when the state says so (blocks until shutdown)."""
        self.odometry.add_listener(self.guard(self._on_odom))
        rospy.on_shutdown(self._return.set)
        while True:
            self._return.wait()         # a return to drive, or shutdown
            if shutting_down():
                return
            self._return.clear()
            ok, reason = self.travel_back()
            if not rospy.is_shutdown() and self.state == state.RETURNING:
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
            self.log.warn('%s', warning)
        loss = self._losses.get(path)
        lost_tail = loaded.lost_after_end(loss.lost) if loss is not None and not resuming else 0
        if lost_tail:
            return False, ('the last %d landmark(s) of the recording could not be written (%s): '
                           'the way back from here is unknown; not travelling back'
                           % (lost_tail, loss.error))
        kept = (self.progress.route or {}).get('heading') if resuming else None
        if kept and self.correction is not None and not self.correction.received:
            try:
                self.correction.install_plain(kept)   # the whole layer restarted mid-return
            except ValueError as error:
                return False, 'cannot resume: %s' % error
        resets = [gap for gap in loaded.gaps if is_untrusted_reset(gap.reason)]
        if resets:
            return False, ('the recording crossed an odometry reset it could not carry across '
                           '(%s, before %s): the way back across it is unknown; not travelling '
                           'back' % (resets[-1].reason, resets[-1].before))
        landmarks, problem = self._in_corrected_frame(loaded.landmarks)
        if problem:
            return False, problem
        goals = list(zip(loaded.labels, landmarks))[::-1]
        if loaded.gaps:
            self.warnings = 'the recording has %d gap(s) (%d landmark(s) lost): the return bridges ' \
                'them' % (len(loaded.gaps), loaded.missing)
            self.log.warn('%s: %s', path, self.warnings)
        if resuming:
            if digest != self.progress.digest or len(goals) != self.progress.landmarks:
                return False, 'landmark file %s changed since the return started' % path
            try:
                route = Route.from_lists((self.progress.route or {}).get('route'))
            except ValueError as error:
                return False, 'cannot resume: the route in %s: %s' % (self.progress_file, error)
        else:
            anchor = self.progress.anchor or self._position()
            if anchor is None:
                return False, 'no odometry for the return: %s' % self.odometry.describe_missing(
                    p.odom_timeout)
            try:
                route = build_route(landmarks, anchor, p)
                if p.prune_loops:
                    route = self._pruned(route, landmarks)
            except ValueError as error:
                return False, 'cannot build the return route: %s' % error
            self._save_progress(self.progress.start(digest, len(goals), time.time(),
                                                    route=self._route_data(route), anchor=anchor))
        self._publish_route(route)
        done = self.progress.completed
        budget = RouteBudget(landmarks)
        self._publish_status()
        self.log.info('%d landmarks, %.2f m, from %s; %s; waiting for %s', len(goals),
                      loaded.total_distance, path, 'resuming after %d' % done if done else 'starting',
                      rospy.resolve_name(names.BACK_TRAVEL))
        if self.client is None:
            self.client = GoalRunner(names.BACK_TRAVEL, BackTravelAction)
        if not self.client.wait_for_server(rospy.Duration(p.server_timeout)):
            return False, ('action server %s not available after %.0f s (is back_travel_server '
                           'running?)' % (rospy.resolve_name(names.BACK_TRAVEL), p.server_timeout))
        problem = self._set_route(route, [landmark for _, landmark in goals], done)
        if problem:
            return False, problem
        remaining = [landmark for _, landmark in goals[done:]]
        allowance = return_allowance(remaining, p.return_timeout_factor, p.return_timeout_margin,
                                     p.slowest_v)
        deadline = rospy.get_time() + allowance
        travelled = self.progress.travelled or 0.0
        for number, (label, landmark) in enumerate(goals[done:], done + 1):
            where = 'goal %d/%d (%s)' % (number, len(goals), label)
            self.client.send(BackTravelGoal(*landmark.as_list()))
            problem = self._wait_for_goal(where, landmark, deadline, allowance,
                                          lambda: budget.problem(travelled + self._goal_distance()))
            if problem:
                return False, problem
            if not self.client.succeeded:
                return False, '%s ended %s' % (where, self.client.describe())
            travelled += self.client.result.distance
            progress = self.progress.goal_done(number, time.time(), self._position(), travelled)
            self._save_progress(progress._replace(route=self._route_data(route)).checked())
            self._publish_status()
        return True, 'travelled %.3f m over %d landmarks%s%s' % (
            travelled, len(goals) - done,
            ' (resumed after %d)' % done if done else '',
            '; ' + self.warnings if self.warnings else '')

    def _pruned(self, route, landmarks):
        """``route`` without the loops the drift allows to cut (core/pruning.py), logged."""
        correction = self.correction.correction if self.correction is not None else None
        result = prune_route(route, landmarks, correction, self.params)
        for line in result.describe():
            self.log.info('%s', line)
        return result.route

    def _goal_distance(self):
        """m driven by the current goal so far (its last feedback)."""
        return self.client.feedback.distance if self.client.feedback is not None else 0.0

    def _in_corrected_frame(self, landmarks):
        """``landmarks`` in the corrected odometry frame; (landmarks, problem)."""
        if self.correction is None:
            return landmarks, None
        deadline = time.monotonic() + self.params.correction_timeout
        while not self.correction.received and time.monotonic() < deadline \
                and not rospy.is_shutdown():
            time.sleep(0.05)
        if not self.correction.received:
            return None, ('no heading correction on %s within %.0f s (is heading_correction '
                          'running?)' % (rospy.resolve_name(names.HEADING_CORRECTION),
                                         self.params.correction_timeout))
        receiver = self.correction
        self.log.info('landmarks in the corrected odometry frame: %s', receiver.correction.describe())
        return correct_landmarks(landmarks, receiver.correction, receiver.reference.yaw), None

    def _wait_for_position(self):
        """The robot's odometry [x, y], waiting (wall-bounded) for it; None if none came."""
        self.odometry.acquire(self.ROLE)
        deadline = time.monotonic() + self.params.server_timeout
        position = self._position()
        while position is None and time.monotonic() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)
            position = self._position()
        return position

    def _route_data(self, route):
        """What the progress keeps of the route: the route itself and, with the heading
        correction, the correction and the corrected frame's state now (a restarted
        layer continues in the same frame)."""
        heading = self.correction.to_plain() if self.correction is not None else None
        return {'route': route.to_lists(), 'heading': heading}

    def _publish_route(self, route):
        """The route the return will drive, latched, for RViz."""
        msg = Path()
        msg.header.stamp, msg.header.frame_id = rospy.Time.now(), self.progress.frame_id or 'odom'
        for index, (x, y) in enumerate(zip(route.x, route.y)):
            pose = PoseStamped()
            pose.header = msg.header
            pose.pose.position.x, pose.pose.position.y = x, y
            q = pose.pose.orientation
            q.x, q.y, q.z, q.w = quaternion_from_yaw(route.direction(min(index, route.vertices - 2))
                                                     if route.vertices > 1 else 0.0)
            msg.poses.append(pose)
        self.route_pub.publish(msg)

    def _set_route(self, route, landmarks, completed):
        """Give the server the route, the landmarks of its goals (return order) and how
        many are done. None if set, else why not."""
        service = rospy.resolve_name(names.SET_RETURN_ROUTE)
        try:
            rospy.wait_for_service(names.SET_RETURN_ROUTE, self.params.server_timeout)
            set_route = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
            response = set_route(header=rospy.Header(stamp=rospy.Time.now(),
                                                     frame_id=self.progress.frame_id or ''),
                                 route=json.dumps(route.to_lists()),
                                 landmarks=[value for lm in landmarks for value in lm.as_list()],
                                 completed=completed)
        except (rospy.ROSException, rospy.ServiceException) as error:
            return 'cannot set the return route on %s: %s' % (service, error)
        return None if response.ok else 'return route refused: %s' % response.message

    def _wait_for_goal(self, where, landmark, deadline, allowance, over_budget):
        """Wait for the goal's result; cancel it and say why on a safety event, the
        goal's backstop, the whole return's allowance or its distance budget
        (``over_budget()``: None or why). None once it ended."""
        p = self.params
        goal_allowance = (p.goal_timeout_factor * expected_duration(landmark, p.slowest_v)
                          + p.goal_timeout_margin)
        while not self.client.wait(WAIT_SLICE):
            now = rospy.get_time()
            if self._trip:
                problem = '%s: safety stop: %s' % (where, self._trip)
            elif self._lost:
                problem = '%s: %s' % (where, self._lost)
            elif now > self.client.heard + goal_allowance:
                problem = '%s: no result and no feedback for %.0f s' % (where, goal_allowance)
            elif now > deadline:
                problem = '%s: the return exceeded its time allowance of %.0f s' % (where, allowance)
            elif rospy.is_shutdown():
                problem = '%s: node shutting down' % where
            elif self.state != state.RETURNING:
                problem = '%s: the mission is %s' % (where, self.state)
            elif over_budget():
                problem = '%s: %s' % (where, over_budget())
            else:
                continue
            self.client.cancel()
            return problem
        return None

    # --- diagnostics ---------------------------------------------------------------------------
    def _mission_status(self, stat):
        stat.add('state', self.state)
        if self.progress is not None:
            stat.add('landmarks', self.progress.landmarks)
            stat.add('completed', self.progress.completed)
        if self.warnings:
            stat.add('warnings', self.warnings)
        if self.state == state.ABORTED:
            stat.summary(diagnostics.ERROR, 'aborted: %s' % self.reason)
        elif self.warnings:
            stat.summary(diagnostics.WARN, '%s: %s' % (self.state, self.warnings))
        else:
            stat.summary(diagnostics.OK, '%s%s' % (self.state, ': ' + self.reason if self.reason else ''))

    def _odometry_status(self, stat):
        blocking = self.state in (state.ROTATING, state.RETURNING)
        diagnostics.age_status(stat, 'odometry', self.odometry.age(), self.params.odom_timeout,
                               diagnostics.ERROR if blocking else diagnostics.WARN,
                               diagnostics.ERROR if blocking else diagnostics.WARN,
                               listening=self.odometry.listening())
        stat.add('refused messages', self.odometry.refused)

    def _file_status(self, stat):
        stat.add('file', self.landmark_file)
        try:
            real = os.path.realpath(self.landmark_file)
            stat.add('mission file', real)
            stat.add('bytes', os.path.getsize(real))
            stat.summary(diagnostics.OK, os.path.basename(real))
        except OSError as error:
            level = diagnostics.ERROR if self.state in (state.RECORDING, state.ROTATING,
                                                        state.RETURNING) else diagnostics.OK
            stat.summary(level, 'no landmark file yet' if level == diagnostics.OK else
                         'landmark file unreadable: %s' % error.strerror)

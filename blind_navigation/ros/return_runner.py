"""The return of the back-travel client (section 3.3.7, Figure 6): loads the
landmarks, expresses them in the heading-corrected frame, plans the route
(core/return_plan.py), sets it on the server and sends the landmarks in reverse order, one goal at a time
(ros/paper_adapter.RemoteGoals),
within each goal's backstop, the whole return's allowance and its distance
budget; the progress is persisted after each goal. The mission's state stays
with the client (ros/back_travel_client.py), which owns this runner.
"""
import os
import time

import rospy

from blind_navigation import names
from blind_navigation.core import mission_state as state, outcome
from blind_navigation.core.back_travel import home_check, stopped
from blind_navigation.core.heading_correction import correct_landmarks
from blind_navigation.core.mission_limits import ReturnWatch
from blind_navigation.core.pause import CONTACT_DEFAULTS, PauseLog
from blind_navigation.core.progress import file_digest
from blind_navigation.core.return_plan import (plan_route, recording_problem, return_goals,
                                               return_warning)
from blind_navigation.core.resume import resumed_route
from blind_navigation.core.store import LandmarkFileError, load_landmarks
from blind_navigation.msg import BackTravelGoal
from blind_navigation.ros.common import wait_wall
from blind_navigation.ros.paper_adapter import RemoteGoals

Ending = outcome.Ending

#: How often the goal wait checks safety events and allowances, s.
WAIT_SLICE = 0.02
#: s (sim) the home check waits for the robot to stop after the last goal.
SETTLE = 2.0


class ReturnRunner(object):
    """Drives the returns of ``mission`` (the BackTravelClient: params, progress, events)."""

    def __init__(self, mission):
        self.mission = mission
        self.params, self.log = mission.params, mission.log
        self.client = RemoteGoals()     # its action client made when the first return starts
        self.pauses = PauseLog(CONTACT_DEFAULTS['contact_wait'])   # the return's takeovers, contacts
        self.home_tolerance = 0.0   # the server's (set with the route); 0: position not checked
        self._left = None       # the landmarks not driven yet, while a return drives

    def distance_left(self):
        """m still to drive home along the landmarks (None: the return has not started)."""
        left = self._left
        if left is None:
            return None
        return max(sum(abs(landmark.d) for landmark in left) - self._goal_distance(), 0.0)

    def cancel(self):
        """Cancel the goal under way, if any."""
        self.client.cancel()

    def travel_back(self):
        """Figure 6: load, reverse, send goal by goal (from the first landmark not
        completed yet), then check the robot is home. Returns (core/outcome code: HOME
        once home, reason), the reason naming the return's takeovers and contacts."""
        self.pauses = PauseLog(CONTACT_DEFAULTS['contact_wait'])
        code, reason = self._travel_back()
        m = self.mission
        self.pauses.update(rospy.get_time(), False, False, m.position)   # the pauses end with the return
        pauses = self.pauses.describe(rospy.get_time())
        return code, '%s; %s' % (reason, pauses) if pauses and pauses not in reason else reason

    def _travel_back(self):
        m = self.mission
        resuming = m.keeper.progress.status == state.RETURNING
        loss = None if resuming else m.recording.loss_of(m.keeper.progress.landmark_file)
        loaded, digest, problem = self._load(m.keeper.progress.landmark_file, loss, resuming)
        if problem:
            return problem
        landmarks, problem = self._in_corrected_frame(loaded.landmarks)
        if problem:
            return problem
        goals = return_goals(loaded.labels, landmarks)
        warning = return_warning(loaded, loss)
        if warning:
            m.warnings = warning
            self.log.warn('%s: %s', m.keeper.progress.landmark_file, m.warnings)
        if resuming:
            route, problem = self._kept_route(digest, len(goals))
        else:
            route, problem = self._new_route(landmarks, digest, len(goals))
        if problem:
            return problem
        m.paths.publish_route(route, m.keeper.progress.frame_id)
        m.publish_status()
        done = m.keeper.progress.completed
        self.log.info('%d landmarks, %.2f m, from %s; %s; waiting for %s', len(goals),
                      loaded.total_distance, m.keeper.progress.landmark_file,
                      'resuming after %d' % done if done else 'starting',
                      rospy.resolve_name(names.BACK_TRAVEL))
        problem = self._connect(route, [landmark for _, landmark in goals], done)
        if problem:
            return problem
        ended = self._drive(goals, done, route, landmarks)
        return self._home(route, ended.reason) if ended.code == outcome.NONE else ended

    def _home(self, route, reason):
        """An Ending once every goal is done: HOME only if the odometry, once the robot
        stopped, is within the server's home tolerance of the route's end (the start)."""
        p = self.params
        odometry = self.mission.odometry
        wait_wall(lambda: stopped(odometry.fresh(p.odom_timeout)), SETTLE)
        odom = odometry.fresh(p.odom_timeout)
        if odom is None:
            return Ending(outcome.ODOMETRY, 'every goal done, but no odometry to check the robot '
                          'is home (%s)' % odometry.describe_missing(p.odom_timeout))
        home, text = home_check(odom, (route.x[-1], route.y[-1]), self.home_tolerance)
        return Ending(outcome.HOME, '%s; %s' % (reason, text)) if home else \
            Ending(outcome.NOT_HOME, text)

    def recording_problem(self):
        """Why the recording as it is now gives no way back (an Ending), or None: asked before the pi
        turn (ros/turn_start.py), while the recording may still grow (the final landmark)."""
        path = os.path.realpath(self.mission.landmark_file)
        try:
            loaded = load_landmarks(path, limits=self.mission.limits, allow_empty=True)
        except LandmarkFileError as error:
            return Ending(outcome.STORAGE, 'landmark file unusable: %s' % error)
        return recording_problem(loaded, self.mission.recording.loss_of(path))

    def _load(self, path, loss, resuming):
        """(loaded landmarks, the file's digest, problem: an Ending) of the recorded file; ``loss``:
        the recorder's core/return_plan.WriteLoss (None when ``resuming``)."""
        m = self.mission
        try:
            loaded = load_landmarks(path, limits=m.limits)
            digest = file_digest(path)
        except OSError as error:
            return None, None, Ending(outcome.STORAGE, 'landmark file unusable: %s: cannot read: %s'
                                      % (path, error.strerror))
        except LandmarkFileError as error:
            return None, None, Ending(outcome.STORAGE, 'landmark file unusable: %s' % error)
        for warning in loaded.warnings:
            self.log.warn('%s', warning)
        problem = m.keeper.restore_heading() if resuming else None    # the layer restarted mid-return
        return loaded, digest, Ending(outcome.RESUME, problem) if problem else \
            recording_problem(loaded, loss)

    def _kept_route(self, digest, goals):
        """(route, problem: an Ending): the route of the return this one resumes."""
        route, problem = resumed_route(self.mission.keeper.progress, digest, goals,
                                       self.mission.keeper.path)
        return route, Ending(outcome.RESUME, problem) if problem else None

    def _new_route(self, landmarks, digest, goals):
        """(route, problem: an Ending): the route planned from where recording stopped, persisted."""
        m, p = self.mission, self.params
        anchor = m.keeper.progress.anchor or m.position()
        if anchor is None:
            return None, Ending(outcome.ODOMETRY, 'no odometry for the return: %s'
                                % m.odometry.describe_missing(p.odom_timeout))
        correction = m.correction.correction if m.correction is not None else None
        try:
            route, lines = plan_route(landmarks, anchor, p, p.prune_loops, correction)
        except ValueError as error:
            return None, Ending(outcome.RECORDING, 'cannot build the return route: %s' % error)
        for line in lines:
            self.log.info('%s', line)
        m.keeper.save(m.keeper.progress.start(digest, goals, time.time(), route=m.keeper.route_data(route),
                                         anchor=anchor))
        return route, None

    def _connect(self, route, landmarks, done):
        """Wait for the action server and set the route on it; None or why not (an Ending)."""
        problem, self.home_tolerance = self.client.connect(
            route, landmarks, done, self.mission.keeper.progress.frame_id or '',
            self.params.server_timeout)
        return Ending(outcome.ROLE_FAILURE, problem) if problem else None

    def _drive(self, goals, done, route, landmarks):
        """Send ``goals[done:]`` one at a time within a core/mission_limits.ReturnWatch
        over ``landmarks``; an Ending (code NONE: every goal done)."""
        m = self.mission
        watch = ReturnWatch(landmarks, [landmark for _, landmark in goals[done:]], self.params,
                            rospy.get_time())
        travelled = m.keeper.progress.travelled or 0.0
        for number, (label, landmark) in enumerate(goals[done:], done + 1):
            where = 'goal %d/%d (%s)' % (number, len(goals), label)
            self._left = [remaining for _, remaining in goals[number - 1:]]
            self.client.send(BackTravelGoal(*landmark.as_list()))
            watch.goal(landmark, self.client.heard)
            problem = self._wait_for_goal(where, watch, lambda: travelled + self._goal_distance())
            if problem:
                return problem
            if not self.client.succeeded:    # the server's cause (none: it failed or is gone)
                return Ending(getattr(self.client.result, 'outcome', 0) or outcome.ROLE_FAILURE,
                              '%s ended %s' % (where, self.client.describe()))
            travelled += self.client.result.distance
            progress = m.keeper.progress.goal_done(number, time.time(), m.position(), travelled)
            m.keeper.save(progress._replace(route=m.keeper.route_data(route)).checked())
            m.publish_status()
        warnings = m.all_warnings()
        return Ending(outcome.NONE, 'travelled %.3f m over %d landmarks%s%s' % (
            travelled, len(goals) - done,
            ' (resumed after %d)' % done if done else '',
            '; ' + warnings if warnings else ''))

    def _goal_distance(self):
        """m driven by the current goal so far (its last feedback)."""
        client = self.client
        return client.feedback.distance if client.feedback is not None else 0.0

    def _in_corrected_frame(self, landmarks):
        """``landmarks`` in the corrected odometry frame; (landmarks, problem)."""
        receiver = self.mission.correction
        if receiver is None:
            return landmarks, None
        if not wait_wall(lambda: receiver.received, self.params.correction_timeout):
            return None, Ending(outcome.ROLE_FAILURE, 'no heading correction on %s within %.0f s (is '
                                'heading_correction running?)' % (
                                    rospy.resolve_name(names.HEADING_CORRECTION),
                                    self.params.correction_timeout))
        self.log.info('landmarks in the corrected odometry frame: %s', receiver.correction.describe())
        # the recording went on after the reference (vision loss) until the turn began
        ended = self.mission.recording_ended
        after = max(0.0, ended - receiver.reference.stamp) if ended is not None else 0.0
        return correct_landmarks(landmarks, receiver.correction, receiver.reference.yaw, after), None

    def _wait_for_goal(self, where, watch, travelled):
        """Wait for the goal's result; cancel it and say why on a safety event or a limit
        of ``watch`` (core/mission_limits.ReturnWatch; ``travelled()``: m so far): an Ending;
        None once it ended. While an operator has taken over or a bumper is pressed, no allowance counts."""
        m = self.mission
        while not self.client.wait(WAIT_SLICE):
            now = rospy.get_time()
            taken, pressed = m.takeover.active(), m.layer.safety.pressed
            if self.pauses.update(now, taken, pressed, m.position):
                m.publish_status()
            watch.heard(self.client.heard)
            watch.update(now, taken or pressed)
            limit = watch.problem(now, travelled())
            if m.trip:      # a contact in the return is the server's (its Contacts)
                problem = Ending(outcome.SAFETY_EVENT, '%s: safety stop: %s' % (where, m.trip))
            elif m.lost:
                problem = Ending(outcome.ODOMETRY, '%s: %s' % (where, m.lost))
            elif rospy.is_shutdown():
                problem = Ending(outcome.CANCELLED, '%s: node shutting down' % where)
            elif m.state != state.RETURNING:    # it has ended: this ending is not announced
                problem = Ending(m.machine.outcome, '%s: the mission is %s' % (where, m.state))
            elif limit:
                problem = Ending(limit.code, '%s: %s' % (where, limit.reason))
            else:
                continue
            self.client.cancel()
            return problem
        return None

"""The paper layout's mission owner (node back_travel_client): ros/mission_owner.MissionOwner
over the same core/mission.Mission, its recording, standstill, pi turn and goals the other
nodes' (core/mission_remote.py), and its hand-shakes with them: the savers' ``storage``, the
turn (``recording_end`` out, ``rotation_done`` in), the return's goals (:class:`RemoteGoals`),
the heading correction and ``role_failure`` (docs/DESIGN.md, "The paper's layout").
"""
import os
from types import SimpleNamespace

import actionlib
import rospy
from actionlib.action_client import CommState, get_name_of_constant
from actionlib_msgs.msg import GoalStatus
from std_msgs.msg import Bool, Empty, String

from blind_navigation import names
from blind_navigation.core import drive, mission_state as state, outcome
from blind_navigation.core.heading_correction import correct_landmarks
from blind_navigation.core.landmark import Limits
from blind_navigation.core.mission import TURN, TURNED
from blind_navigation.core.mission_remote import Remote
from blind_navigation.core.return_plan import NO_LOSS, damage_warning, plan_return, recording_problem, write_loss
from blind_navigation.core.role_params import BACK_TRAVEL_CLIENT, BACK_TRAVEL_SERVER
from blind_navigation.core.route import SECTION_FIELDS
from blind_navigation.core.safety import is_contact
from blind_navigation.core.store import LandmarkFileError, load_landmarks
from blind_navigation.msg import (BackTravelAction, BackTravelGoal, HeadingCorrection, ReturnRoute,
                                  RouteSection, StorageUsage)
from blind_navigation.ros.common import ros_home_file, subscribe
from blind_navigation.ros.landmark_saving import LANDMARK_FILE
from blind_navigation.ros.layer import correction_from_message
from blind_navigation.ros.mission_owner import MissionOwner
from blind_navigation.srv import SetReturnRoute

def paper_params(layer):
    """(params, Mission settings, the landmark file, None: nothing driven here) of the client."""
    client = layer.params('back_travel_client', BACK_TRAVEL_CLIENT)
    params = SimpleNamespace(**dict(BACK_TRAVEL_SERVER.make(control='time')._asdict(), **client._asdict()))
    params.listeners = 0
    settings = dict(heading_correction=client.heading_correction, standstill=client,
                    prune_loops=client.prune_loops, on_vision_back=client.on_vision_back,
                    turn_tolerance=client.turn_tolerance, vision_back_grace=client.vision_back_grace,
                    limits=client, remote_goals=True, remote=Remote(client.heading_correction))
    return params, settings, ros_home_file(LANDMARK_FILE, client.landmark_file), None


class SaverFile(object):
    """The saver's landmark file as core/mission's store, read only; ``losses``: the WriteLoss
    reported per real path; ``damage``, ``space.warning``: as the saver's ``storage`` says."""

    def __init__(self, path, losses, limits):
        self.path, self.losses, self.limits = path, losses, limits
        self.damage, self.space, self.loaded = '', SimpleNamespace(warning=''), None

    def problem(self, allow_empty=True):
        """Why the file gives no way back (a core/outcome.Ending), or None; the file read kept."""
        try:
            self.loaded = load_landmarks(os.path.realpath(self.path), limits=self.limits,
                                         allow_empty=allow_empty)
        except (OSError, LandmarkFileError) as error:
            return outcome.Ending(outcome.STORAGE, 'landmark file unusable: %s' % error)
        return recording_problem(self.loaded, self.loss())

    def load(self):
        self.problem()
        return self.loaded

    def loss(self):
        return self.losses.get(os.path.realpath(self.path), NO_LOSS)

    def warning(self):
        return self.damage

    def close(self):
        """The saver's."""


class PaperOwner(MissionOwner):
    """The mission's owner of the paper layout (module docstring)."""

    ROLE = 'back_travel_client'
    SCHEMA = BACK_TRAVEL_CLIENT
    RECORDS = False
    configure = staticmethod(paper_params)

    def _open_store(self):
        """A mission's file, the saver's; the goals' client (made once)."""
        self.turn_begun = self.connected = False
        self.remote_goals = getattr(self, 'remote_goals', None) or RemoteGoals(self.guard)
        self.losses = getattr(self, 'losses', {})     # real path of a landmark file -> its WriteLoss
        return SaverFile(self.landmark_file, self.losses, Limits(self.params.max_v, self.params.max_w))

    def _subscribe(self):
        super(PaperOwner, self)._subscribe()
        guard = self.guard
        subscribe(names.ROLE_FAILURE, String, guard(self._on_failure), queue_size=10)
        subscribe(names.STORAGE, StorageUsage, guard(self._on_storage), queue_size=5)
        self.end_pub = rospy.Publisher(names.RECORDING_END, Empty, queue_size=1, latch=True)
        subscribe(names.ROTATION_DONE, Bool, guard(lambda msg: self._on_rotation_done(msg.data)), queue_size=1)
        if self.mission.config.heading_correction:
            subscribe(names.HEADING_CORRECTION, HeadingCorrection, guard(self._on_correction), queue_size=1)

    def _on_failure(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        if sender != rospy.get_name():          # this process's roles report at once
            self._on_fault('%s (%s)' % (msg.data, sender))

    def _on_storage(self, msg):
        loss = write_loss(msg, msg.error)     # a StorageUsage names what its writer lost
        if msg.lost:
            self.losses[os.path.realpath(msg.file)] = loss
        with self.lock:
            self.mission.config.remote.reported(msg.distance)
            damage = damage_warning(loss, msg.file) if msg.lost or msg.error else ''
            if (damage, msg.space_warning) != (self.store.damage, self.store.space.warning):
                self.store.damage, self.store.space.warning = damage, msg.space_warning
                self.publish_status()
        self.inbox.put()

    def _on_correction(self, msg):
        with self.lock:
            if self.mission.state == state.ROTATING:
                self.mission.config.remote.measured = correction_from_message(msg)[0]

    def _on_rotation_done(self, ok):
        """rotate_pi's end of the turn: the mission's turn takes it (a failed one ends the
        standstill too; a turn not committed yet cannot have succeeded)."""
        with self.lock:
            if self.mission.state != state.ROTATING:
                return
            safety = ', '.join(self.layer.safety.active)
            result = drive.Outcome(drive.SUCCEEDED, '') if ok else drive.Outcome(
                drive.FAILED, 'the pi rotation failed%s; not travelling back' % (
                    ' (safety stop: %s)' % safety if safety else ''),
                outcome.TURN if not safety else outcome.CONTACTS if is_contact(safety) else
                outcome.SAFETY_EVENT)
            if self.mission.phase != TURN and not ok:
                self._cancel(result.reason, result.cause)
            elif self.mission.phase != TURN:
                self.log.error('rotation_done true refused: the pi turn has not begun (the recording goes on)')
            else:
                self.inbox.put(goal_result=result)

    def _step(self, now, odom, visual, events):
        m = self.mission
        if m.state == state.RECORDING and (events.get('vision_lost') or 'go_home' in m.requests):
            problem = self.store.problem()      # asked again at the commit, and after the turn
            if problem:
                self._cancel('%s, but %s' % ('vision lost' if events.get('vision_lost') else
                                             'return requested (go_home)', problem.reason), problem.code)
        if m.phase == TURNED and not self.connected:
            self._start_return()
        step = super(PaperOwner, self)._step(now, odom, visual, events)
        remote = self.mission.config.remote
        if step.phase == TURN and not self.turn_begun:
            self.turn_begun = True
            self.end_pub.publish(Empty())     # the sampling publisher's final sample, then the turn
            self.log.info('the pi turn begins: recording ended')
        if remote.refused:
            self.log.error('rotation_done true refused: %s', remote.refused)
            remote.refused = ''
        if step.goal is not None:
            self.remote_goals.send(step.goal[1], lambda result: self.inbox.put(goal_result=result))
        return step

    def _start_return(self):
        """The turn done (or a return resumed): the saver's landmarks, the route set on the server."""
        m, self.connected = self.mission, True
        if m.kept is None:
            problem = self.store.problem(allow_empty=False)
            if problem:
                return self._cancel(problem.reason, problem.code)
            m.loaded = loaded = self.store.loaded
            m.configure_return(landmarks=correct_landmarks(loaded.landmarks, m.correction)
                               if m.correction is not None else loaded.landmarks)
        try:
            planned = (m.kept.route, None) if m.kept is not None else plan_return(
                m.landmarks, m.anchor, self.params, m.config.prune_loops, m.correction)
        except ValueError as error:
            return self._cancel('cannot build the return route: %s' % error, outcome.RECORDING)
        done = m.kept.done if m.kept is not None else 0
        problem, response = self.remote_goals.connect(planned[0], m.landmarks[::-1], done,
                                                      self.layer.odometry.frame_id or '',
                                                      self.params.server_timeout)
        if problem:
            return self._cancel(problem, outcome.ROLE_FAILURE)
        self.params.home_tolerance = response.home_tolerance
        m.configure_return(mode=response.control, planned=planned)   # the route planned once
        return None

    def _announce(self):
        super(PaperOwner, self)._announce()
        if self.mission.state in state.TERMINAL:
            self.remote_goals.cancel()

    def _on_shutdown(self):
        self.remote_goals.cancel()
        super(PaperOwner, self)._on_shutdown()


def route_message(route):
    """The ReturnRoute message of a core/route.Route."""
    return ReturnRoute(version=ReturnRoute.ROUTE_VERSION, x=route.x, y=route.y, speed=route.speed,
                       corner=route.corner,
                       sections=[RouteSection(*[getattr(s, f) for f in SECTION_FIELDS]) for s in route.sections])


class RemoteGoals(object):
    """The return's goals on back_travel_server, one at a time, each goal's callbacks bound to
    it; the action client made at the first :meth:`connect`."""

    def __init__(self, guard):
        self.guard, self.client, self._handle = guard, None, None

    def connect(self, route, landmarks, completed, frame_id, timeout):
        """Wait for the server, then set the route, its goals' ``landmarks`` (return order) and
        how many are ``completed``: (why not or None, the response)."""
        if self.client is None:
            self.client = actionlib.ActionClient(names.BACK_TRAVEL, BackTravelAction)
        if not self.client.wait_for_server(rospy.Duration(timeout)):
            return ('action server %s not available after %.0f s (is back_travel_server running?)'
                    % (rospy.resolve_name(names.BACK_TRAVEL), timeout)), None
        try:
            rospy.wait_for_service(names.SET_RETURN_ROUTE, timeout)
            call = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
            response = call(header=rospy.Header(stamp=rospy.Time.now(), frame_id=frame_id),
                            route=route_message(route),
                            landmarks=[value for lm in landmarks for value in lm.as_list()],
                            completed=completed)
        except (rospy.ROSException, rospy.ServiceException) as error:
            return 'cannot set the return route on %s: %s' % (rospy.resolve_name(names.SET_RETURN_ROUTE), error), None
        return None if response.ok else 'return route refused: %s' % response.message, response

    def send(self, landmark, on_done):
        """Send the goal of ``landmark``; ``on_done(core/drive.Outcome)`` once it ended."""
        ended = []

        def on_transition(handle):
            if handle.get_comm_state() != CommState.DONE or ended:
                return
            ended.append(handle)
            status, text, result = handle.get_goal_status(), handle.get_goal_status_text(), handle.get_result()
            if status == GoalStatus.SUCCEEDED:
                return on_done(drive.Outcome(drive.SUCCEEDED, ''))
            name = get_name_of_constant(GoalStatus, status)
            on_done(drive.Outcome(drive.FAILED, 'ended %s' % ('%s: %s' % (name, text) if text else name),
                                  getattr(result, 'outcome', 0) or outcome.ROLE_FAILURE))

        self._handle = self.client.send_goal(BackTravelGoal(*landmark.as_list()),
                                             self.guard(on_transition))

    def cancel(self):
        """Ask the server to cancel the goal under way, if any."""
        if self._handle is not None and self._handle.get_comm_state() != CommState.DONE:
            self._handle.cancel()


"""The paper layout's mission owner (node back_travel_client): ros/mission_owner.MissionOwner
over the same core/mission.Mission, its recording, standstill, pi turn and goals the other
nodes' (core/mission_remote.Remote, RemoteReturn), through ros/paper_adapter.py.
docs/DESIGN.md, "The paper's layout".
"""
import os
from types import SimpleNamespace

from blind_navigation.core import drive, mission_state as state, outcome
from blind_navigation.core.heading_correction import correct_landmarks
from blind_navigation.core.landmark import Limits
from blind_navigation.core.mission import TURN, TURNED
from blind_navigation.core.mission_remote import Remote
from blind_navigation.core.return_plan import damage_warning, plan_return, recording_problem
from blind_navigation.core.role_params import BACK_TRAVEL_CLIENT, BACK_TRAVEL_SERVER
from blind_navigation.core.safety import is_contact
from blind_navigation.core.store import LandmarkFileError, load_landmarks
from blind_navigation.ros.landmark_saving import landmark_file
from blind_navigation.ros.mission_owner import MissionOwner
from blind_navigation.ros.paper_adapter import (RemoteGoals, RemoteRecording, RemoteTurn,
                                                subscribe_correction, subscribe_failures, write_loss)


def paper_params(layer):
    """(params, Mission settings, the landmark file, None: nothing driven here) of the client."""
    client = layer.params('back_travel_client', BACK_TRAVEL_CLIENT)
    params = SimpleNamespace(**dict(BACK_TRAVEL_SERVER.make(control='time')._asdict(), **client._asdict()))
    params.listeners = 0
    settings = dict(heading_correction=client.heading_correction, standstill=client,
                    prune_loops=client.prune_loops, on_vision_back=client.on_vision_back,
                    turn_tolerance=client.turn_tolerance, vision_back_grace=client.vision_back_grace,
                    limits=client, remote_goals=True, remote=Remote(client.heading_correction))
    return params, settings, landmark_file(client.landmark_file), None


class SaverFile(object):
    """The saver's landmark file as core/mission's store, read only: load (the last good
    one if it cannot be read now: :meth:`problem` asked first), the reported loss."""

    def __init__(self, path, losses, limits):
        self.path, self.losses, self.limits = path, losses, limits
        self.error, self.damage, self.space, self.loaded = '', '', SimpleNamespace(warning=''), None

    def problem(self, allow_empty=True):
        """Why the file gives no way back (a core/outcome.Ending: unreadable, or
        core/return_plan.recording_problem), or None; the file read kept for :meth:`load`."""
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
        return self.losses(self.path)

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
        return SaverFile(self.landmark_file, lambda path: self.reports.loss_of(path),
                         Limits(self.params.max_v, self.params.max_w))

    def _subscribe(self):
        super(PaperOwner, self)._subscribe()
        subscribe_failures(self.guard, self._on_fault)
        self.reports = RemoteRecording(self.guard, self._on_storage)
        self.remote_turn = RemoteTurn(self.guard, self._on_rotation_done)
        if self.mission.config.heading_correction:
            subscribe_correction(self.guard, self._on_correction)

    # --- the other nodes ---------------------------------------------------------------------
    def _on_storage(self, msg):
        with self.lock:
            self.mission.config.remote.reported(msg.distance)
            damage = damage_warning(write_loss(msg), msg.file) if msg.lost or msg.error else ''
            if (damage, msg.space_warning) != (self.store.damage, self.store.space.warning):
                self.store.damage, self.store.space.warning = damage, msg.space_warning
                self.publish_status()
        self.inbox.put()

    def _on_correction(self, correction):
        with self.lock:
            if self.mission.state == state.ROTATING:
                self.mission.config.remote.measured = correction

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

    # --- the loop ----------------------------------------------------------------------------
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
            self.remote_turn.begin()
            self.log.info('the pi turn begins: recording ended')
        if remote.refused:
            self.log.error('rotation_done true refused: %s', remote.refused)
            remote.refused = ''
        if step.goal is not None:
            self.remote_goals.send(step.goal[1], lambda result: self.inbox.put(goal_result=result))
        return step

    def _start_return(self):
        """The turn done (or a return resumed): the landmarks as the saver finished them,
        the route set on back_travel_server (its mode and home tolerance the mission's)."""
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

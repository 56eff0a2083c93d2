"""The mission owner's services (std_srvs/Trigger), served by back_travel_client (their
replies, :func:`reply`, also by ros/mission_owner.py).

``go_home`` (in ``recording``: the return, as ``vision_lost``), ``cancel`` (``aborted``,
every output halted) and ``new_mission`` (from a terminal state: a new mission id, state
``idle``, a new file); elsewhere refused naming the state
(core/mission_state.*_refusal; docs/safety.md, "One state machine").
"""
import threading

import rospy
from std_srvs.srv import Trigger, TriggerResponse

from blind_navigation import names
from blind_navigation.core import mission_state as state, outcome
from blind_navigation.core.mission_files import mission_number, next_mission_id
from blind_navigation.ros.layer import MISSION_ID


#: The answers of an acknowledged ``go_home`` (% the state) and ``cancel``.
GO_HOME_DONE = 'returning home: the mission is %s'
CANCELLED = 'stopped: the mission is aborted (%s)' % state.CANCELLED


def caller(request):
    """The node that called a service (its connection header's callerid), or '?'."""
    return request._connection_header.get('callerid', '?')


def reply(log, request, what, refusal, done):
    """The Trigger response of the service ``what``: refused for ``refusal`` (WARN), else
    acknowledged with ``done`` (INFO); the log names the caller. Every mission owner's."""
    if refusal is not None:
        log.warn('%s from %s %s', what, caller(request), refusal)
        return TriggerResponse(success=False, message=refusal)
    log.info('%s from %s: %s', what, caller(request), done)
    return TriggerResponse(success=True, message=done)


def new_mission_done(number, landmark_file):
    """The answer of an acknowledged ``new_mission``: mission ``number``'s file."""
    return ('mission %d: idle; recording into a new file behind %s from the first landmark'
            % (number, landmark_file))


class MissionServices(object):
    """``go_home``, ``cancel`` and ``new_mission`` of ``mission`` (the BackTravelClient)."""

    def __init__(self, mission):
        self.mission = mission
        self._new_lock = threading.Lock()   # one new_mission at a time
        self.services = [rospy.Service(names.GO_HOME, Trigger, mission.guard(self._on_go_home)),
                         rospy.Service(names.CANCEL, Trigger, mission.guard(self._on_cancel)),
                         rospy.Service(names.NEW_MISSION, Trigger,
                                       mission.guard(self._on_new_mission))]

    def _on_go_home(self, request):
        m = self.mission
        refusal = state.go_home_refusal(m.state)
        if refusal is None and not m.begin_return('return requested (go_home by %s)'
                                                  % caller(request)):
            refusal = 'the return did not start: the mission is %s (%s)' % (m.state, m.reason)
        return reply(m.log, request, 'go_home', refusal, GO_HOME_DONE % m.state)

    def _on_cancel(self, request):
        m = self.mission
        refusal = state.cancel_refusal(m.state)
        if refusal is None and m.abort(state.CANCELLED, outcome.CANCELLED):     # every MotionOutput halts
            m.runner.cancel()
        else:
            refusal = refusal or state.cancel_refusal(m.state)
        return reply(m.log, request, 'cancel', refusal, CANCELLED)

    def _on_new_mission(self, request):
        m = self.mission
        with self._new_lock:
            old, done = m.state, None
            refusal = state.new_mission_refusal(old)
            if refusal is None:
                new_id = next_mission_id(m.layer.current_mission_id())
                rospy.set_param(MISSION_ID, new_id)         # before the roles see idle
                number = mission_number(m.layer.current_mission_id())
                self._forget_return()
                if m.move(old, state.IDLE, 'mission %d (new_mission by %s)' % (number, caller(request))):
                    done = new_mission_done(number, m.landmark_file)
                else:   # only new_mission (under this lock) leaves a terminal state: not reached
                    refusal = 'refused: the mission became %s meanwhile' % m.state
        return reply(m.log, request, 'new_mission', refusal, done)

    def _forget_return(self):
        """The last mission's return forgotten: its progress (the file is replaced at the next
        return; a restart ignores it, another mission's), turn timeout, trip, lost frame,
        warnings and RViz paths. The roles reset their own on ``idle``."""
        m = self.mission
        m.turn.forget()
        m.keeper.progress = None
        m.trip = m.lost = None
        m.warnings = ''
        m.paths.clear()

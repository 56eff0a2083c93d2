"""The mission owner's services (std_srvs/Trigger), served by back_travel_client.

``go_home`` (in ``recording``: the return, as ``vision_lost``), ``cancel`` (``aborted``,
every output halted) and ``new_mission`` (from a terminal state: a new mission id, state
``idle``, a new file); elsewhere refused naming the state
(core/mission_state.*_refusal; docs/safety.md, "One state machine").
"""
import threading

import rospy
from std_srvs.srv import Trigger, TriggerResponse

from blind_navigation import names
from blind_navigation.core import mission_state as state
from blind_navigation.core.mission_files import mission_number, next_mission_id
from blind_navigation.ros.layer import MISSION_ID


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
        sender = request._connection_header.get('callerid', '?')
        refusal = state.go_home_refusal(m.state)
        if refusal is None and m.begin_return('return requested (go_home by %s)' % sender):
            return TriggerResponse(success=True, message='returning home: the mission is %s'
                                   % m.state)
        refusal = refusal or 'the return did not start: the mission is %s (%s)' % (m.state, m.reason)
        m.log.warn('go_home from %s %s', sender, refusal)
        return TriggerResponse(success=False, message=refusal)

    def _on_cancel(self, request):
        m = self.mission
        sender = request._connection_header.get('callerid', '?')
        refusal = state.cancel_refusal(m.state)
        if refusal is None and m.abort(state.CANCELLED):     # every MotionOutput halts
            m.runner.cancel()
            m.log.warn('cancel from %s: stopped', sender)
            return TriggerResponse(success=True, message='stopped: the mission is aborted (%s)'
                                   % state.CANCELLED)
        refusal = refusal or state.cancel_refusal(m.state)
        m.log.warn('cancel from %s %s', sender, refusal)
        return TriggerResponse(success=False, message=refusal)

    def _on_new_mission(self, request):
        m = self.mission
        sender = request._connection_header.get('callerid', '?')
        with self._new_lock:
            old = m.state
            refusal = state.new_mission_refusal(old)
            if refusal is None:
                new_id = next_mission_id(m.layer.current_mission_id())
                rospy.set_param(MISSION_ID, new_id)         # before the roles see idle
                number = mission_number(m.layer.current_mission_id())
                self._forget_return()
                if m.move(old, state.IDLE, 'mission %d (new_mission by %s)' % (number, sender)):
                    return TriggerResponse(success=True, message=(
                        'mission %d: idle; recording into a new file behind %s from the first '
                        'landmark' % (number, m.landmark_file)))
                # only new_mission (under this lock) leaves a terminal state: not reached
                refusal = 'refused: the mission became %s meanwhile' % m.state
            m.log.warn('new_mission from %s %s', sender, refusal)
            return TriggerResponse(success=False, message=refusal)

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

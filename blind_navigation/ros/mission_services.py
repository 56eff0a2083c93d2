"""The mission owner's services (std_srvs/Trigger), served by back_travel_client.

``blind_navigation/go_home``: the manual trigger, acknowledged: while
``recording`` it starts the return on the same path as
``blind_navigation/vision_lost`` (the reason says it was requested); in any
other state it is refused (success false) naming the state.
``blind_navigation/cancel``: stop now: the mission ``aborted`` ("cancelled by
request"), which halts every MotionOutput of the layer (ros/motion.py; in the
paper's layout through the latched state), and the goal under way is
cancelled; in a terminal state it is refused naming the state. The rules:
core/mission_state.go_home_refusal and cancel_refusal. Why: docs/safety.md.
"""
import rospy
from std_srvs.srv import Trigger, TriggerResponse

from blind_navigation import names
from blind_navigation.core import mission_state as state


class MissionServices(object):
    """``go_home`` and ``cancel`` of ``mission`` (the BackTravelClient)."""

    def __init__(self, mission):
        self.mission = mission
        self.services = [rospy.Service(names.GO_HOME, Trigger, mission.guard(self._on_go_home)),
                         rospy.Service(names.CANCEL, Trigger, mission.guard(self._on_cancel))]

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

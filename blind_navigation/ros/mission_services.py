"""The replies of the mission owner's services (std_srvs/Trigger, ros/mission_owner.py):
``go_home`` (in ``recording``: the return, as ``vision_lost``), ``cancel`` (``aborted``,
every output halted) and ``new_mission`` (from a terminal state: a new mission id, state
``idle``, a new file); elsewhere refused naming the state (core/mission_state.*_refusal).
"""
from std_srvs.srv import TriggerResponse

from blind_navigation.core import mission_state as state


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


"""A landmark asked of a core/mission.Mission by the paper's ``record_landmark`` service:
:func:`hand_in` hands it to the recording (taken in time order, then answered);
:func:`withdraw` answers one not taken in time (docs/recording.md)."""
import math

from .mission import RECORDING
from .sample_log import FINAL, SAMPLE

#: The answer to a ``final`` request (docs/recording.md says why).
FINAL_REFUSED = ("refused: 'final' is not taken here: the mission takes its final landmark "
                 'itself when vision is lost or go_home is called (a recorder request never '
                 'ends the recording nor starts the return)')


class LandmarkRequest(object):
    """``command``, ``yaw``, ``period``, ``stamp``; ``answer`` (label, why not), then ``answered``."""

    def __init__(self, command, yaw, period, stamp, answered=None):
        self.command, self.yaw, self.period = command, yaw, period
        self.stamp = stamp or None
        self.answered, self.answer = answered, None

    def reply(self, label, why_not=''):
        """Answer it (the first answer counts)."""
        if self.answer is None:
            self.answer = (label or '', '' if label else why_not)
            if self.answered is not None:
                self.answered(self)


def problem(request):
    """Why ``request`` is bad whatever the mission's state, or None."""
    if request.command == FINAL:
        return FINAL_REFUSED
    if request.command != SAMPLE:
        return 'refused: unknown command %r (expected %r)' % (request.command, SAMPLE)
    if not (math.isfinite(request.yaw) and math.isfinite(request.period) and request.period > 0):
        return 'refused: psi and T must be finite and T > 0, got psi %r, T %r' % (
            request.yaw, request.period)
    if request.stamp is not None and not math.isfinite(request.stamp):
        return 'refused: the stamp %r is not a time' % (request.stamp,)
    return None


def hand_in(mission, request):
    """Give ``request`` to ``mission``'s recording or answer why not; under the owner's lock."""
    why = problem(request)
    recording = mission.recording
    if why is None and mission.phase != RECORDING:
        why = 'refused: the mission is %s, not recording (landmarks are taken only while ' \
              'recording)' % mission.state
    elif why is None and not recording.started:
        why = 'refused: no odometry yet, the recording has not started (the mission is %s)' % (
            mission.state)
    elif why is None and request.stamp is not None and request.stamp < recording.last_tick - 1e-9:
        why = 'refused: stamped %.3f s, before the last landmark (%.3f s): landmarks are taken ' \
              'in time order' % (request.stamp, recording.last_tick)
    if why is not None:
        request.reply('', why)
    else:
        recording.requested.append(request)


def withdraw(mission, request, waited):
    """Answer ``request`` if not taken within ``waited`` s. Under the mission's owner's lock."""
    if request in mission.recording.requested:
        mission.recording.requested.remove(request)
    if mission.phase != RECORDING:
        request.reply('', 'not taken: the recording ended (the mission is %s)' % mission.state)
    else:
        request.reply('', 'not taken within %.1f s: no odometry state after its stamp' % waited)

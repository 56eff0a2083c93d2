"""Safety rules of the return: its velocity limits (:func:`goal_limits`), its time
(:func:`return_allowance`), the Kobuki's :class:`SafetyEvents`, a SetReturnRoute's landmarks."""
import math
from collections import namedtuple

from .landmark import landmark_from_values

#: Defaults of the safety params (the nodes expose them as ~private params).
SAFETY_DEFAULTS = {
    'correction_w': 0.3,       # rad/s a goal may turn beyond its recorded |w| (closed-loop steering)
    'slowest_v': 0.03,         # m/s assumed for landmarks recorded slower, when timing a goal
}


class VelocityLimits(namedtuple('VelocityLimits', 'max_v max_w')):
    """Largest |v| (m/s) and |w| (rad/s) to command."""

    __slots__ = ()

    def clamp(self, v, w):
        """``(v, w)`` scaled by one factor (the curvature kept) into the limits; non-finite: 0."""
        if not (math.isfinite(v) and math.isfinite(w)):
            return 0.0, 0.0
        factor = min(1.0, self.max_v / abs(v) if abs(v) > self.max_v else 1.0,
                     self.max_w / abs(w) if abs(w) > self.max_w else 1.0)
        return v * factor, w * factor


def recorded_speed(landmark):
    """How fast the robot went over ``landmark``, m/s: the larger of its end |v| and mean d / T."""
    return max(abs(landmark.v), landmark.d / landmark.T)


def goal_limits(landmark, max_v, max_w, correction_w=SAFETY_DEFAULTS['correction_w']):
    """Limits for driving ``landmark`` back: ``max_v``/``max_w``, never faster than recorded
    (:func:`recorded_speed`; |w| + ``correction_w``)."""
    if max_v < 0 or max_w < 0 or correction_w < 0:
        raise ValueError('limits must not be negative: max_v %r, max_w %r, correction_w %r'
                         % (max_v, max_w, correction_w))
    return VelocityLimits(min(max_v, recorded_speed(landmark)),
                          min(max_w, abs(landmark.w) + correction_w))


def expected_duration(landmark, slowest_v=SAFETY_DEFAULTS['slowest_v']):
    """s a goal should take: its period T, or d at its recorded |v| (>= ``slowest_v``) if longer."""
    return max(landmark.T, landmark.d / max(abs(landmark.v), slowest_v))


def return_allowance(landmarks, factor, margin, slowest_v=SAFETY_DEFAULTS['slowest_v']):
    """s allowed for a whole return: ``factor`` x the expected durations + ``margin``."""
    return factor * sum(expected_duration(lm, slowest_v) for lm in landmarks) + margin

#: kind -> (sensor names by index, the state value that means "stop", its word)
EVENT_LAYOUT = {
    'bumper': (('left', 'center', 'right'), 1, 'pressed'),       # BumperEvent.PRESSED
    'cliff': (('left', 'center', 'right'), 1, 'cliff'),          # CliffEvent.CLIFF
    'wheel_drop': (('left', 'right'), 1, 'dropped'),             # WheelDropEvent.DROPPED
}
#: The kind a return survives as a contact (core/pause.Contacts); the others stay terminal.
CONTACT = 'bumper'


def is_contact(reason):
    """True when ``reason`` (a SafetyEvents reason) is a bumper contact."""
    return reason.startswith(CONTACT + ' ')


class SafetyEvents(object):
    """Which Kobuki safety sensors are active; :meth:`update` (one event's fields): the reason to
    stop when a sensor becomes active, else None."""

    def __init__(self):
        self._active = {}       # (kind, index) -> reason
        self._released = {}     # kind -> time (update's ``now``) a sensor of it was last released

    def update(self, kind, index, sensor_state, now=None):
        if kind not in EVENT_LAYOUT:
            raise ValueError('unknown safety event kind %r (expected one of %s)'
                             % (kind, ', '.join(sorted(EVENT_LAYOUT))))
        names, stop_value, word = EVENT_LAYOUT[kind]
        name = names[index] if 0 <= index < len(names) else 'sensor %d' % index
        key = (kind, index)
        if sensor_state != stop_value:
            if self._active.pop(key, None) is not None and now is not None:
                self._released[kind] = now
            return None
        reason = '%s %s %s' % (kind.replace('_', ' '), name, word)
        self._active[key] = reason
        return reason

    def continues(self, kind, now, window):
        """True when an event of ``kind`` at ``now`` continues one under way: one of its sensors
        is active, or was released less than ``window`` s before."""
        released = self._released.get(kind)
        return any(active == kind for active, _ in self._active) or (
            released is not None and 0.0 <= now - released < window)

    @property
    def active(self):
        """Reasons of the sensors active now (empty: safe to drive)."""
        return sorted(self._active.values())

    @property
    def terminal(self):
        """Reasons of the active sensors other than the bumper (cliff, wheel drop)."""
        return [reason for reason in self.active if not is_contact(reason)]

def landmarks_from_flat(values):
    """Landmarks of a SetReturnRoute's flat [v, w, d, T, psi, ...]; ValueError naming a bad one."""
    if len(values) % 5:
        raise ValueError('completed landmarks: %d numbers is not a multiple of 5' % len(values))
    landmarks = []
    for index in range(0, len(values), 5):
        try:
            landmarks.append(landmark_from_values(list(values[index:index + 5])))
        except ValueError as error:
            raise ValueError('completed landmark %d: %s' % (index // 5 + 1, error))
    return landmarks

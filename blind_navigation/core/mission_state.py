"""The mission's one state machine, obeyed by every role of the layer: the states, the table
``TRANSITIONS`` (every change through :meth:`MissionState.transition`, atomic), who may move
(:func:`may_move`), the services' refusals (``*_refusal``). docs/DESIGN.md, "The state machine".
"""
import threading

IDLE, RECORDING, ROTATING, RETURNING = 'idle', 'recording', 'rotating', 'returning'
HOME, ABORTED, RECOVERED = 'home', 'aborted', 'recovered'
DOCKING, DOCKED = 'docking', 'docked'       # dock_at_home: the Kobuki's auto-docking (core/docking)

ALL = (IDLE, RECORDING, ROTATING, RETURNING, HOME, ABORTED, RECOVERED, DOCKING, DOCKED)
#: The mission has ended here; ``new_mission`` starts the next one from any of them.
TERMINAL = (HOME, ABORTED, RECOVERED, DOCKED)

#: Allowed transitions: state -> the states it may move to. ``None`` is the owner
#: before its first state: idle, or (a restarted owner) a resumed return or its abort.
TRANSITIONS = {
    None: (IDLE, RETURNING, ABORTED),
    IDLE: (RECORDING, ABORTED),
    RECORDING: (ROTATING, HOME, ABORTED),      # home: nothing to retrace (nothing_to_retrace)
    ROTATING: (RETURNING, RECORDING, RECOVERED, ABORTED),
    RETURNING: (HOME, RECOVERED, ABORTED, DOCKING),
    DOCKING: (DOCKED, HOME, ABORTED),          # home: the docking failed, saying why
}
TRANSITIONS.update((ended, (IDLE,)) for ended in TERMINAL)     # new_mission

#: The role that may command motion in a state (none in ``docking``: the dock drive does);
#: the one-off gyro calibration runs outside any mission.
ROTATION_ROLE, BACK_TRAVEL_ROLE, CALIBRATION_ROLE = 'rotate_pi', 'back_travel_server', 'calibrate_gyro'
MOTION_OWNER = {ROTATING: ROTATION_ROLE, RETURNING: BACK_TRAVEL_ROLE}
#: The reason of a ``cancel``'s ``aborted``.
CANCELLED = 'cancelled by request'


def go_home_refusal(state):
    """Why ``go_home`` is refused in ``state`` (None: it starts the return)."""
    return None if state == RECORDING else \
        'refused: the mission is %s (go_home starts the return only while %s)' % (state, RECORDING)


def cancel_refusal(state):
    """Why ``cancel`` is refused in ``state`` (None: the mission is aborted)."""
    ended = state in TERMINAL or state is None
    return 'refused: the mission is %s (nothing to cancel)' % state if ended else None


def new_mission_refusal(state):
    """Why ``new_mission`` is refused in ``state`` (None: the next mission starts)."""
    if state in TERMINAL:
        return None
    return 'refused: the mission is %s (new_mission starts the next one only once it is %s)' % (
        state, ' or '.join(TERMINAL))


def starts_new_mission(old, new):
    """True when ``old -> new`` is ``new_mission``: the roles start recording again."""
    return old in TERMINAL and new == IDLE


def may_move(role, state):
    """True when ``role`` may command motion in ``state`` (None: no mission, only the calibration)."""
    return role == CALIBRATION_ROLE if state is None else MOTION_OWNER.get(state) == role


def records(state):
    """True while the path may still be recorded (up to ``rotating``: its end is the owner's decision)."""
    return state in (None, IDLE, RECORDING, ROTATING)


#: ``on_vision_back`` policies in the turn or the return: go on home (the paper's), or stop
#: ``recovered`` (core/mission); before the turn vision back resumes the recording.
ON_VISION_BACK = ('home', 'stop')


class IllegalTransition(ValueError):
    """A transition that :data:`TRANSITIONS` does not allow (a programming error)."""


def check_transition(old, new):
    """Raise :class:`IllegalTransition` unless ``old -> new`` is in :data:`TRANSITIONS`."""
    if new not in TRANSITIONS.get(old, ()):
        raise IllegalTransition('illegal mission state transition %s -> %s' % (old, new))


class MissionState(object):
    """The mission's state, its reason and its core/outcome code, changed only by
    :meth:`transition` and :meth:`abort` (atomic: check and set under one lock, the class's,
    so that a copy shares it: sim/harness.py tries several returns from one state)."""
    _lock = threading.Lock()

    def __init__(self):
        self.state, self.reason, self.outcome = None, '', 0

    def transition(self, expected, new, reason='', outcome=0):
        """Move ``expected -> new`` if the state is ``expected``: True if it moved (False: an event
        late or raced); IllegalTransition if the table forbids it. ``outcome``: a terminal's code."""
        check_transition(expected, new)
        with self._lock:
            if self.state != expected:
                return False
            self.state, self.reason, self.outcome = new, reason, outcome if new in TERMINAL else 0
            return True

    def abort(self, reason, outcome):
        """Move any unfinished state to ``aborted`` with the code ``outcome``: (moved, the state before)."""
        with self._lock:
            old = self.state
            if old in TERMINAL:
                return False, old
            check_transition(old, ABORTED)
            self.state, self.reason, self.outcome = ABORTED, reason, outcome
            return True, old

"""The mission's one state machine, obeyed by every role of the layer.

States ``idle -> recording -> rotating -> returning -> home`` (dock_at_home: ``-> docking ->
docked``), ``aborted`` and ``recovered`` (:data:`TERMINAL`, back to ``idle`` only by ``new_mission``);
the table ``TRANSITIONS``, every change through :meth:`MissionState.transition` (atomic); who
may move (:data:`MOTION_OWNER`, :func:`may_move`); the services' refusals (``*_refusal``).
docs/DESIGN.md, "The state machine".
"""
import threading

IDLE = 'idle'
RECORDING = 'recording'
ROTATING = 'rotating'
RETURNING = 'returning'
HOME = 'home'
ABORTED = 'aborted'
RECOVERED = 'recovered'
DOCKING = 'docking'         # dock_at_home: the Kobuki's auto-docking drives (core/docking)
DOCKED = 'docked'

ALL = (IDLE, RECORDING, ROTATING, RETURNING, HOME, ABORTED, RECOVERED, DOCKING, DOCKED)
#: The mission has ended here; ``new_mission`` starts the next one from any of them
#: (a new terminal state is one more name here: TRANSITIONS and the rules follow).
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

#: The role that may command motion in a state (the roles are the layer's node classes).
ROTATION_ROLE = 'rotate_pi'
BACK_TRAVEL_ROLE = 'back_travel_server'
#: The one-off gyro calibration runs outside any mission (no state) and may spin then.
CALIBRATION_ROLE = 'calibrate_gyro'
#: In ``docking`` none of the layer's roles moves: the Kobuki's dock drive does, past the mux.
MOTION_OWNER = {ROTATING: ROTATION_ROLE, RETURNING: BACK_TRAVEL_ROLE}


#: The state in which ``go_home`` starts the return (as vision loss does).
GO_HOME_FROM = RECORDING
#: The reason of a ``cancel``'s ``aborted``.
CANCELLED = 'cancelled by request'


def go_home_refusal(state):
    """Why ``go_home`` is refused in ``state`` (None: it starts the return)."""
    if state == GO_HOME_FROM:
        return None
    return 'refused: the mission is %s (go_home starts the return only while %s)' % (
        state, GO_HOME_FROM)


def cancel_refusal(state):
    """Why ``cancel`` is refused in ``state`` (None: the mission is aborted)."""
    if state in TERMINAL or state is None:
        return 'refused: the mission is %s (nothing to cancel)' % state
    return None


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
    """True when ``role`` may command motion while the mission is in ``state``
    (None: no mission is running, which only the calibration may use)."""
    if state is None:
        return role == CALIBRATION_ROLE
    return MOTION_OWNER.get(state) == role


def records(state):
    """True while the path may still be recorded (before the first landmark, after it, and in
    ``rotating`` until the pi turn begins: the recording's end is the owner's decision)."""
    return state in (None, IDLE, RECORDING, ROTATING)


#: ``on_vision_back`` policies: go on home (the paper's), or stop ``recovered``.
ON_VISION_BACK = ('home', 'stop')


def vision_back_state(state, turn_begun, policy):
    """The state vision back moves ``state`` to (None: no change): ``recording`` while the
    pi turn has not begun (a brief loss), ``recovered`` during the turn or the return
    with policy ``stop``."""
    if state == ROTATING and not turn_begun:
        return RECORDING
    if state in (ROTATING, RETURNING) and policy == 'stop':
        return RECOVERED
    return None


class IllegalTransition(ValueError):
    """A transition that :data:`TRANSITIONS` does not allow (a programming error)."""


def check_transition(old, new):
    """Raise :class:`IllegalTransition` unless ``old -> new`` is in :data:`TRANSITIONS`."""
    if new not in TRANSITIONS.get(old, ()):
        raise IllegalTransition('illegal mission state transition %s -> %s' % (old, new))


class MissionState(object):
    """The mission's state, its reason and its outcome code (core/outcome: the cause of a
    terminal state, 0 before), changed only by :meth:`transition` and :meth:`abort`
    (atomic: check and set under one lock)."""

    def __init__(self):
        self._lock = threading.Lock()
        self.state = None
        self.reason = ''
        self.outcome = 0

    def __deepcopy__(self, _memo):
        """A copy with its own lock (sim/harness.py tries several returns from one state)."""
        copied = MissionState()
        copied.state, copied.reason, copied.outcome = self.state, self.reason, self.outcome
        return copied

    def transition(self, expected, new, reason='', outcome=0):
        """Move ``expected -> new`` if the state is ``expected``; True if it moved,
        False if the state was another (an event late or raced: the caller ignores
        it). An ``expected -> new`` the table forbids raises IllegalTransition.
        ``outcome``: the code of a terminal ``new`` (0 for the others)."""
        check_transition(expected, new)
        with self._lock:
            if self.state != expected:
                return False
            self.state, self.reason, self.outcome = new, reason, outcome if new in TERMINAL else 0
            return True

    def abort(self, reason, outcome):
        """Move any unfinished state to ``aborted`` with the code ``outcome``: (moved, the
        state before); a mission that had already ended is not moved (only ``new_mission``
        leaves a terminal state)."""
        with self._lock:
            old = self.state
            if old in TERMINAL:
                return False, old
            check_transition(old, ABORTED)
            self.state, self.reason, self.outcome = ABORTED, reason, outcome
            return True, old

"""The mission's docking (dock_at_home): :class:`Docking` asks the owner once for the Kobuki's
auto-docking (Step.dock) and ends ``docked`` or ``home`` ('docking failed: <why>') on its
result, a takeover or :data:`DOCK_TIMEOUT`. docs/safety.md, "Docking"."""
import collections

from . import mission_state, outcome

DOCK = 'dock'               # the mission's phase while docking
#: s the docking may take from the return's arrival (docs/safety.md, "Docking").
DOCK_TIMEOUT = 180.0

DockingResult = collections.namedtuple('DockingResult', 'docked text')
DockingResult.__doc__ = 'The auto-docking action\'s end: docked (on the charger) and its text (why not).'


class Docking(object):
    """The docking after the return arrived with ``home_reason`` at ``now``; ``timeout``: s it
    may take (None: :data:`DOCK_TIMEOUT`)."""

    def __init__(self, home_reason, now, timeout=None):
        self.home_reason, self.started = home_reason, now
        self.timeout = DOCK_TIMEOUT if timeout is None else float(timeout)
        self.start = True          # the owner sends the docking goal (Step.dock) at this step

    def requested(self):
        """True once: the step that should send the docking goal."""
        start, self.start = self.start, False
        return start

    def step(self, now, inputs):
        """None while the docking goes on (nothing published: the dock drive drives), else the
        mission's end (state, core/outcome code, reason): ``docked``, or ``home`` naming why not."""
        result = inputs.docking
        if result is not None and result.docked:
            return mission_state.DOCKED, outcome.DOCKED, 'docked on the charger (%s); the return: %s' % (
                result.text or 'auto-docking succeeded', self.home_reason)
        if result is not None:
            why = result.text or 'the auto-docking action failed'
        elif inputs.operator:
            why = '%s (the auto-docking goal is cancelled)' % inputs.operator
        elif now - self.started > self.timeout + 1e-9:
            why = 'not docked within %.0f s of the arrival (dock_timeout)' % self.timeout
        else:
            return None
        return mission_state.HOME, outcome.DOCK_FAILED, 'docking failed: %s; the return: %s' % (
            why, self.home_reason)

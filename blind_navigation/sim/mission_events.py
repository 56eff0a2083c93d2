"""Scripted events of a simulated mission (sim/harness.py's ``events`` setting): a
bumper pressed, an operator driving, the motors off (the robot blocked), requests and
vision events, each at a time after the mission's start, the pi turn's, the return's or the
final approach's.
"""
import collections

#: kinds with a length (windows) and the moments (fired once)
WINDOWS = ('bumper', 'takeover', 'motors_off')   # motors_off: the wheels stop (a blocked robot)
MOMENTS = ('cancel', 'go_home', 'vision_lost', 'vision_back', 'odometry_reset', 'time_back', 'cliff')
ORIGINS = ('start', 'turn', 'return', 'approach')   # approach: the final approach's start

Event = collections.namedtuple('Event', 'kind origin at length command')
Event.__new__.__defaults__ = (0.0, (0.0, 0.0))
Event.__doc__ = ('``kind`` (:data:`WINDOWS`, :data:`MOMENTS`) ``at`` s after ``origin`` '
                 '(:data:`ORIGINS`); windows last ``length`` s; a takeover sends ``command`` (v, w).')


class ScriptedEvents(object):
    """The events of one run; :meth:`origin` dates each origin once it is reached."""

    def __init__(self, events=()):
        self.events = [Event(*event) for event in events]
        for event in self.events:
            if event.kind not in WINDOWS + MOMENTS or event.origin not in ORIGINS:
                raise ValueError('unknown event %r (kinds %s, origins %s)'
                                 % (event, ', '.join(WINDOWS + MOMENTS), ', '.join(ORIGINS)))
        self.origins = {'start': 0.0}
        self.fired = set()

    def origin(self, name, now):
        """The ``name`` origin is reached at ``now`` (the first time counts)."""
        self.origins.setdefault(name, now)

    def _since(self, event, now):
        start = self.origins.get(event.origin)
        return None if start is None else now - start - event.at

    def fire(self, kind, now):
        """True once for each event of ``kind`` whose time has come."""
        if not self.events:
            return False
        for index, event in enumerate(self.events):
            since = self._since(event, now)
            if event.kind == kind and index not in self.fired and since is not None and since >= -1e-9:
                self.fired.add(index)
                return True
        return False

    def window(self, kind, now):
        """The event of ``kind`` under way at ``now``, or None."""
        if not self.events:
            return None
        for event in self.events:
            since = self._since(event, now)
            if event.kind == kind and since is not None and -1e-9 <= since < event.length - 1e-9:
                return event
        return None

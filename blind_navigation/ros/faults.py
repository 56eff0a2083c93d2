"""A role that fails ends the mission safely: the one wrapper of every thread
target and callback a role registers (docs/safety.md, "A role that fails").

``guard = layer.guard(role)``; ``guard(fn)`` is ``fn`` that, on an unexpected
exception (any ``Exception`` not raised while the node shuts down), calls
:meth:`Faults.fail` and returns None instead of raising. ``fail(role, error)``:

1. halts every velocity output of this process for good (ros/motion.halt_all);
2. logs the traceback (rospy.logfatal);
3. reports ``<role> failed: <Type>: <message>`` to the mission's owner: at once
   to the callbacks of this process (:meth:`Faults.on_failure`, the owner when
   hosted here) and on ``blind_navigation/role_failure`` (std_msgs/String,
   latched) for an owner in another process; the owner ends the mission
   ``aborted`` with that reason;
4. turns this process's ``role failures`` diagnostics status to ERROR.

Steps 2-4 happen once per role and place (a callback failing at every message
reports once; the mission is over); a repeat halts again, is counted and
logged in one line at most every :data:`REPEAT_LOG_PERIOD` s (wall).
"""
import functools
import threading
import time
import traceback

import rospy

from . import diagnostics as diag
from .common import shutting_down

#: s (wall) between two log lines of a failure repeating at one place
REPEAT_LOG_PERIOD = 5.0


def describe(role, error):
    """The reason a failure of ``role`` gives, naming the exception's type and message."""
    return '%s failed: %s: %s' % (role, type(error).__name__, error)


class Faults(object):
    """The failures of this process's roles. ``diagnostics``: ros/diagnostics.Diagnostics
    (``add``, ``now``); ``publish(text)``: the report to another process's owner;
    ``halt(reason)``: stops every velocity output of this process."""

    def __init__(self, diagnostics, publish, halt):
        self._diagnostics, self._publish, self._halt = diagnostics, publish, halt
        self._lock = threading.Lock()
        self._logged = {}           # (role, place) -> when (wall) it was last logged
        self._callbacks = []
        self.failures = []          # the reasons, in order (one per role and place)
        self.repeats = 0            # failures at a place that had failed already
        diagnostics.add('role failures', self._status)

    def guard(self, role):
        """A decorator-like function: ``guard(fn)`` runs ``fn`` and fails ``role`` on an
        exception (module docstring)."""
        def wrap(fn):
            @functools.wraps(fn)
            def guarded(*args, **kwargs):
                try:
                    return fn(*args, **kwargs)
                except Exception as error:  # noqa: B902 -- what this module is for
                    if shutting_down():
                        rospy.logdebug('%s: %s while shutting down', role, error)
                        return None
                    self.fail(role, error, place=getattr(fn, '__qualname__', repr(fn)))
                    return None
            return guarded
        return wrap

    def on_failure(self, callback):
        """Call ``callback(reason)`` at every failure of a role of this process."""
        self._callbacks.append(callback)

    def fail(self, role, error, place=''):
        """``role`` failed with ``error`` (an exception, in its ``except`` block: its
        traceback is logged) at ``place`` (where, e.g. a method's name): stop, report,
        diagnose (module docstring)."""
        reason = describe(role, error)
        self._halt(reason)
        now = time.monotonic()
        with self._lock:
            last = self._logged.get((role, place))
            if last is None or now - last >= REPEAT_LOG_PERIOD:
                self._logged[(role, place)] = now
            self.repeats += last is not None
            if last is None:
                self.failures.append(reason)
        if last is not None:
            if now - last >= REPEAT_LOG_PERIOD:
                rospy.logerr('%s: %s again in %s', rospy.get_name(), reason, place)
            return
        rospy.logfatal('%s: %s in %s; stopping the robot and ending the mission:\n%s',
                       rospy.get_name(), reason, place or '?', traceback.format_exc())
        for callback in list(self._callbacks):
            try:
                callback(reason)
            except Exception:  # noqa: B902 -- the report must reach the others
                rospy.logfatal('%s: reporting %s failed:\n%s', rospy.get_name(), reason,
                               traceback.format_exc())
        try:
            self._publish(reason)
        except rospy.ROSException:
            pass                    # shutting down
        self._diagnostics.now()

    def _status(self, stat):
        with self._lock:
            failures = list(self.failures)
        stat.add('failures', len(failures))
        stat.add('repeats', self.repeats)
        if failures:
            stat.summary(diag.ERROR, failures[-1] if len(failures) == 1 else
                         '%s (and %d more)' % (failures[0], len(failures) - 1))
        else:
            stat.summary(diag.OK, 'no role failed')

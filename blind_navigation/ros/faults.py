"""A role that fails or a topic wired wrong ends the mission safely (docs/safety.md, "A role that
fails", "Bad input"): the process's fault registry (:func:`declare`), :class:`Faults`, whose guard
wraps every callback, and :class:`Expected`, what a topic must carry (:func:`refuse`)."""
import functools
import threading
import time
import traceback

import rospy

from blind_navigation.core import outcome

from . import diagnostics as diag

#: s (wall) between two log lines of a failure repeating at one place
REPEAT_LOG_PERIOD = 5.0

# The process's fault registry: a refused topic (:func:`refuse`) or a failed role.
_lock = threading.Lock()
_faults = {}          # key (a resolved topic, a role and place) -> the fault's text
_codes = {}           # the fault's text -> its core/outcome code
_listeners = []       # f(fault)
_shutting_down = threading.Event()
rospy.on_shutdown(_shutting_down.set)   # the first hook of the process: it imports this early


def shutting_down():
    """True once the node's shutdown is requested (``rospy.is_shutdown()``: after every hook ran)."""
    return _shutting_down.is_set()


def declare(key, fault, code=outcome.ROLE_FAILURE):
    """A fault ``fault`` (its core/outcome ``code``) at ``key``, once per key (else False)."""
    with _lock:
        if key in _faults:
            return False
        _faults[key] = fault
        _codes.setdefault(fault, code)
        listeners = list(_listeners)
    for listener in listeners:      # each one: a failing listener must not keep an output moving
        try:
            listener(fault)
        except Exception as error:
            rospy.logerr('%s: while declaring %s: %s: %s', rospy.get_name(), fault,
                         type(error).__name__, error)
    return True


def on_fault(callback):
    """``callback(fault)`` on every fault declared, at once for those declared already."""
    with _lock:
        _listeners.append(callback)
        faults = list(_faults.values())
    for fault in faults:
        callback(fault)


def code_of(fault):
    """The core/outcome code declared with ``fault`` (another process's: ROLE_FAILURE)."""
    with _lock:
        return _codes.get(fault, outcome.ROLE_FAILURE)


def faulty():
    """True once a fault was declared (no lock: asked at every command)."""
    return bool(_faults)


class Expected(object):
    """A topic must carry one of ``types`` (``pkg/Name``), with ``md5sum`` if given."""

    def __init__(self, types, md5sum=None):
        self.types = tuple(types)
        self.md5sum = md5sum
        self._accepted = None       # the last connection header accepted (identity)

    @classmethod
    def of(cls, data_class):
        """The type and MD5 sum of a message class."""
        return cls((data_class._type,), data_class._md5sum)

    def __str__(self):
        return ' or '.join(self.types)

    def mismatch(self, found_type, found_md5=None):
        """None when ``found_type`` (and ``found_md5``, unless None or ``*``) is expected, else what."""
        if found_type not in self.types:
            return found_type or 'a message without a type'
        if self.md5sum and found_md5 not in (None, '*', self.md5sum):
            return '%s with MD5 sum %s (another version: %s expected)' % (found_type, found_md5,
                                                                           self.md5sum)
        return None

    def accepts(self, topic, header):
        """True if the connection ``header`` carries this type; else refused and False."""
        if header is self._accepted:
            return True
        found = self.mismatch(header.get('type'), header.get('md5sum'))
        if found is None:
            self._accepted = header
            return True
        refuse(topic, self, found)
        return False


def refuse(topic, expected, found):
    """``topic`` carries ``found``, not ``expected``: declared, then one FATAL line per topic."""
    topic = rospy.resolve_name(topic)
    fault = 'wrong wiring: %s carries %s, expected %s' % (topic, found, expected)
    if declare(topic, fault, outcome.WIRING):    # once per topic: the outputs stopped, the owner told
        rospy.logfatal('%s: %s: refused, nothing moves (fix the remap and start the layer again)',
                       rospy.get_name(), fault)


def check_types(topic_types, expected_by_topic):
    """Refuse each topic of ``expected_by_topic`` whose type in ``topic_types`` (the master's) differs."""
    types = dict(topic_types)
    for topic, expected in expected_by_topic.items():
        found = types.get(topic)
        if found is not None and expected.mismatch(found) is not None:
            refuse(topic, expected, expected.mismatch(found))


class Faults(object):
    """The failures of this process's roles, on ``diagnostics``."""

    def __init__(self, diagnostics):
        self._diagnostics = diagnostics
        self._lock = threading.Lock()
        self._logged = {}           # (role, place) -> when (wall) it was last logged
        self.failures = []          # the reasons, in order (one per role and place)
        self.repeats = 0            # failures at a place that had failed already
        diagnostics.add('role failures', self._status)

    def guard(self, role):
        """``guard(fn)`` runs ``fn`` and fails ``role`` on an exception."""
        def wrap(fn):
            @functools.wraps(fn)
            def guarded(*args, **kwargs):
                try:
                    return fn(*args, **kwargs)
                except Exception as error:  # noqa: B902 -- what this module is for
                    if shutting_down():
                        rospy.logdebug('%s: %s while shutting down', role, error)
                    else:
                        self.fail(role, error, place=getattr(fn, '__qualname__', repr(fn)))
                    return None
            return guarded
        return wrap

    def fail(self, role, error, place=''):
        """``role`` failed with ``error`` (in its ``except`` block) at ``place``: declared once."""
        reason = '%s failed: %s: %s' % (role, type(error).__name__, error)
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
        rospy.logfatal('%s: %s in %s; stopping the robot, ending the mission:\n%s',
                       rospy.get_name(), reason, place or '?', traceback.format_exc())
        declare('%s in %s' % (role, place), reason)   # zero velocity, the owner aborts
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

"""Loops and timers that go on across ROS time moving back (docs/safety.md, "Time that moves
back"): :class:`LoopClock`, :func:`every`, :func:`action_server`."""
import threading
import time
from types import SimpleNamespace

import actionlib
import rospy

#: wall s: a loop warns at most once in this long (the next warning counts the jumps since)
WARN_PERIOD = 10.0


def describe(jump, before, now):
    """The words every warning and abort uses for a jump back of ``jump`` s."""
    return ('the ROS time moved back %.3f s (from %.3f s to %.3f s: a restarted simulator, or '
            'a clock set back?)' % (jump, before, now))


class LoopClock(object):
    """The ROS clock as the loop ``loop`` sees it; ``then``: what it does after a jump (warned)."""

    def __init__(self, loop, log=None, then='going on'):
        self.loop, self.then = loop, then
        self._warn = log.warn if log is not None else rospy.logwarn
        self._seen = self._warned_at = None     # ROS time last looked; wall time last warned
        self._unwarned = 0          # jumps since then not warned about
        self.moved_back = 0.0       # s the time moved back in all
        self.last_jump = None       # (jump, before, now) of the last jump back, s

    def now(self):
        """rospy.get_time(), noting a jump back since this loop last looked."""
        return self._look()[0]

    def _look(self):
        """(now, s the time moved back since the last look)."""
        now = rospy.get_time()
        before, self._seen = self._seen, now
        if before is None or now >= before:
            return now, 0.0
        jump = before - now
        self.moved_back += jump
        self.last_jump = (jump, before, now)
        wall = time.monotonic()
        if self._warned_at is not None and wall - self._warned_at < WARN_PERIOD:
            self._unwarned += 1
        else:
            more = ' (%d more jump(s) back before this one)' % self._unwarned if self._unwarned else ''
            self._warn('%s: %s%s; %s', self.loop, describe(jump, before, now), more, self.then)
            self._warned_at, self._unwarned = wall, 0
        return now, jump

    def sleep(self, seconds, rate=None):
        """rospy.sleep(``seconds``) or ``rate.sleep()``, ended by a jump back; s it moved back."""
        jump = self._look()[1]
        try:
            rate.sleep() if rate is not None else rospy.sleep(seconds)
        except rospy.ROSTimeMovedBackwardsException:
            if rate is not None:
                rate.last_time = rospy.get_rostime()
        return jump + self._look()[1]

    def rate(self, hz):
        """A rospy.Rate of ``hz`` whose ``sleep()`` returns s the time moved back instead of raising."""
        rate = rospy.Rate(hz)
        return SimpleNamespace(sleep=lambda: self.sleep(None, rate))


def every(period, callback, loop, log=None):
    """``callback()`` every ``period`` s of ROS time in a thread, until the returned Event is set."""
    stop = threading.Event()

    def run():
        rate = LoopClock(loop, log).rate(1.0 / period)
        try:
            while not stop.is_set() and not rospy.is_shutdown():
                rate.sleep()
                if not stop.is_set():
                    callback()
        except rospy.ROSInterruptException:
            pass                    # a sleep at shutdown
    threading.Thread(target=run, name=loop, daemon=True).start()
    return stop


def action_server(name, action, guard, on_goal, on_cancel=None, status_period=None, log=None):
    """A started actionlib.ActionServer (callbacks through ``guard``) without actionlib's status
    timer (ended by the time moving back): the status at each transition, every ``status_period`` s."""
    callbacks = [guard(on_goal)] + ([guard(on_cancel)] if on_cancel is not None else [])
    server = actionlib.ActionServer(name, action, *callbacks, auto_start=False)
    rospy.set_param('~actionlib_status_frequency', 0.0)
    server.start()
    if status_period is not None:
        every(status_period, guard(server.publish_status), 'action status', log)
    return server


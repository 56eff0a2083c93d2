"""The layer's /diagnostics: one Updater per process, its statuses added by the roles (what
blocks the return an ERROR, what degrades it a WARN), every ``~diagnostic_period`` s."""
import diagnostic_updater
import rospy
from diagnostic_msgs.msg import DiagnosticStatus

from .clock import every

DEFAULT_PERIOD = 1.0    # s, diagnostic_updater's
OK, WARN, ERROR = DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR


class Diagnostics(object):
    """``hardware_id``: what the statuses are about (the robot's namespace, or 'none')."""

    def __init__(self, hardware_id):
        self.guard = lambda check: check
        self.updater = diagnostic_updater.Updater()
        self.updater.setHardwareID(hardware_id or 'none')
        period = rospy.get_param('~diagnostic_period', DEFAULT_PERIOD)
        if isinstance(period, bool) or not isinstance(period, (int, float)) or not period > 0:
            raise ValueError('~diagnostic_period must be a positive number of seconds, got %r'
                             % (period,))
        every(period, self.now, 'diagnostics')     # on across the ROS time moving back

    def add(self, name, check):
        """Publish the status ``name`` filled by ``check(stat)`` at every update."""
        def task(stat):
            self.guard(check)(stat)
            return stat
        self.updater.add(name, task)

    def now(self):
        """Publish every status now (the master unreachable: a warning, never a fault)."""
        try:
            self.updater.force_update()
        except rospy.ROSException:
            pass  # shutting down
        except OSError as error:
            rospy.logwarn_throttle(10.0, '%s: diagnostics not published: %s (the master?)',
                                   rospy.get_name(), error)


def age_status(stat, what, age, stale, level_when_stale, missing_level=ERROR, listening=None):
    """``stat`` of a stream last heard ``age`` s ago (None: never); ``listening`` (s since
    subscribed, if known): nothing heard yet is OK for ``stale`` s."""
    if listening is not None and listening <= stale and (age is None or age > listening):
        stat.summary(OK, 'waiting for the first %s (listening for %.2f s)' % (what, listening))
        return
    if age is None:
        stat.summary(missing_level, 'no %s received yet' % what)
        return
    stat.add('age (s)', '%.2f' % age)
    if age > stale:
        stat.summary(level_when_stale, '%s is %.1f s old' % (what, age))
    else:
        stat.summary(OK, '%s fresh (%.2f s)' % (what, age))

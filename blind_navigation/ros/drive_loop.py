"""DriveLoop: the one control loop of every behaviour that moves the robot.

Runs a core/drive.Behaviour at ``control_rate`` on the shared odometry: each
cycle core/drive.DriveCycle decides (its end, a Kobuki event, a cancel, the
mission leaving the behaviour's state, the odometry grace), then the
behaviour's ``step`` gives the command, published through ros/motion.MotionOutput.
It returns a typed core/drive.Outcome; every exit but success halts the
output (zero velocity). Why: docs/back_travel.md, "The drive loop".
"""
import rospy

from blind_navigation.core.allowance import HOLD
from blind_navigation.core.drive import (CANCELLED, ODOMETRY_LOST, SAFETY_STOP, DriveCycle,
                                         Outcome)


class DriveLoop(object):
    """Drives behaviours on ``output`` from ``odometry`` (ros/odometry.OdometryFeed).
    ``params``: control_rate, odom_timeout and (with ``grace``) odom_grace."""

    def __init__(self, output, odometry, safety, params, log, guard, grace=True):
        self.output, self.odometry, self.safety = output, odometry, safety
        self.params, self.log, self.grace = params, log, grace
        self.tripped = None
        safety.on_trip(guard(self._on_trip))

    def _on_trip(self, reason):
        self.tripped = reason

    def run(self, behaviour, label, wait=0.0, cancelled=None, inactive=None):
        """Drive ``behaviour`` to its Outcome. ``wait``: s to wait for fresh odometry
        before starting; ``cancelled()``: True to stop; ``inactive()``: why the
        mission no longer lets it move, or None; ``label`` prefixes the log."""
        self.tripped = None
        outcome = self._drive(behaviour, label, wait, cancelled or (lambda: False),
                              inactive or (lambda: None))
        if not outcome.ok:
            self.output.halt(outcome.kind)
        return outcome

    def _drive(self, behaviour, label, wait, cancelled, inactive):
        p, odometry = self.params, self.odometry
        if self.safety.active:
            return Outcome(SAFETY_STOP, ', '.join(self.safety.active))
        odom = odometry.wait_fresh(p.odom_timeout, wait)
        if odom is None:
            return Outcome(ODOMETRY_LOST, odometry.describe_missing(p.odom_timeout))
        behaviour.start(odom)
        self.output.release()
        cycle = DriveCycle(behaviour, p if self.grace else None, p.odom_timeout)
        rate = rospy.Rate(p.control_rate)
        try:
            while True:
                now, age = rospy.get_time(), odometry.age()
                tripped = self.tripped or ', '.join(self.safety.active)
                decision, message = cycle.decide(now, None if age is None else now - age, tripped,
                                                 cancelled() or rospy.is_shutdown(), inactive())
                if message:
                    failed = isinstance(decision, Outcome)
                    (self.log.error if failed else self.log.warn)('%s: %s', label, message)
                if isinstance(decision, Outcome):
                    return self._lost(decision) if decision.kind == ODOMETRY_LOST else decision
                odom = odometry.fresh(p.odom_timeout) if decision != HOLD else None
                if odom is None and decision != HOLD and not self.grace:
                    return self._lost(Outcome(ODOMETRY_LOST, ''))
                if odom is None:        # stale (or the frame was just lost): hold still
                    self.output.stop()
                    rate.sleep()
                    continue
                command = behaviour.step(odom, now)
                if isinstance(command, Outcome):
                    return command
                self.output.publish(*command)
                rate.sleep()
        except rospy.ROSInterruptException:
            return Outcome(CANCELLED, 'node shutdown')

    def _lost(self, outcome):
        """The odometry outcome, saying what is missing."""
        missing = self.odometry.describe_missing(self.params.odom_timeout)
        return outcome._replace(reason='%s (%s)' % (outcome.reason, missing)
                                if self.grace else missing)

"""DriveLoop: calibrate_gyro's control loop (its spins; the mission's drives:
ros/drive_node.py). Runs a core/drive.Behaviour at ``control_rate`` on fresh odometry
(core/drive.DriveCycle decides, ros/motion.MotionOutput publishes) and returns a typed
core/drive.Outcome; every exit but success halts the output.
"""
import rospy

from blind_navigation.core import outcome
from blind_navigation.core.drive import CANCELLED, FAILED, ODOMETRY_LOST, SAFETY_STOP, DriveCycle, Outcome
from blind_navigation.ros.clock import LoopClock, describe


class DriveLoop(object):
    """Drives behaviours on ``output`` from ``odometry`` (ros/odometry.OdometryFeed);
    ``params``: control_rate, odom_timeout; stale odometry ends a run."""

    def __init__(self, output, odometry, safety, params, log, guard):
        self.output, self.odometry, self.safety, self.params, self.log = output, odometry, safety, params, log
        self.tripped = None
        safety.on_trip(guard(self._on_trip))

    def _on_trip(self, reason):
        self.tripped = reason

    def run(self, behaviour, label):
        """Drive ``behaviour`` to its Outcome (``label`` names it in the log)."""
        self.tripped = None
        outcome = self._drive(behaviour, label)
        if not outcome.ok:
            self.output.halt(outcome.kind)
        return outcome

    def _drive(self, behaviour, label):
        p, odometry = self.params, self.odometry
        if self.safety.active:
            return Outcome(SAFETY_STOP, ', '.join(self.safety.active))
        odom = odometry.fresh(p.odom_timeout)
        if odom is None:
            return Outcome(ODOMETRY_LOST, odometry.describe_missing(p.odom_timeout))
        behaviour.start(odom)
        self.output.release()
        cycle = DriveCycle(behaviour, None, p.odom_timeout)
        clock = LoopClock(label, self.log, then='the %s ends (its times and odometry are of the old '
                          'clock)' % label)
        rate = clock.rate(p.control_rate)
        try:
            while True:
                if rate.sleep():
                    return Outcome(FAILED, describe(*clock.last_jump), outcome.CLOCK)
                now, age = rospy.get_time(), odometry.age()
                tripped = self.tripped or ', '.join(self.safety.active)
                decision, _ = cycle.decide(now, None if age is None else now - age, tripped,
                                           rospy.is_shutdown())
                odom = odometry.fresh(p.odom_timeout) if decision is None else None
                if decision is None and odom is None:
                    decision = Outcome(ODOMETRY_LOST, '')
                if isinstance(decision, Outcome):
                    return decision._replace(reason=odometry.describe_missing(p.odom_timeout)) \
                        if decision.kind == ODOMETRY_LOST else decision
                command = behaviour.step(odom, now)
                if isinstance(command, Outcome):
                    return command
                self.output.publish(*command)
        except rospy.ROSInterruptException:
            return Outcome(CANCELLED, 'node shutdown')

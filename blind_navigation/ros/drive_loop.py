"""DriveLoop: the one control loop of every behaviour that moves the robot.

Runs a core/drive.Behaviour at ``control_rate`` on the shared odometry (core/drive.DriveCycle
decides, ros/motion.MotionOutput publishes) and returns a typed core/drive.Outcome;
every exit but success halts the output. A bumper contact (given core/pause.Contacts)
and an operator's takeover pause the behaviour (docs/back_travel.md, "The drive loop").
"""
from collections import deque

import rospy

from blind_navigation.core import outcome
from blind_navigation.core.allowance import HOLD
from blind_navigation.core.drive import (CANCELLED, FAILED, ODOMETRY_LOST, PREEMPTED, SAFETY_STOP,
                                         TAKEN_OVER, DriveCycle, Outcome)
from blind_navigation.core.pause import PAUSE
from blind_navigation.core.safety import is_contact
from blind_navigation.ros.clock import LoopClock, describe


class DriveLoop(object):
    """Drives behaviours on ``output`` from ``odometry`` (ros/odometry.OdometryFeed).
    ``params``: control_rate, odom_timeout and (with ``grace``) odom_grace;
    ``takeover``: the process's ros/takeover.TakeoverWatch, or None."""

    def __init__(self, output, odometry, safety, params, log, guard, grace=True, takeover=None):
        self.output, self.odometry, self.safety = output, odometry, safety
        self.params, self.log, self.grace, self.takeover = params, log, grace, takeover
        self.tripped = self.contacts = None
        self.bumps = deque()            # bumper presses (reasons) since the last cycle
        self.taken = None               # the takeover of the pause under way
        safety.on_trip(guard(self._on_trip))

    def _on_trip(self, reason):
        if self.contacts is not None and is_contact(reason):
            self.bumps.append(reason)   # counted by the run's contacts (a press between cycles too)
        else:
            self.tripped = reason

    def run(self, behaviour, label, wait=0.0, cancelled=None, inactive=None, contacts=None):
        """Drive ``behaviour`` to its Outcome. ``wait``: s to wait for fresh odometry
        before starting; ``cancelled()``: True to stop; ``inactive()``: why the
        mission no longer lets it move, or None; ``contacts``: core/pause.Contacts
        (a bumper press pauses), None (it stops the run); ``label`` prefixes the log."""
        self.tripped, self.taken, self.contacts = None, None, contacts
        self.bumps.clear()
        try:
            outcome = self._drive(behaviour, label, wait, cancelled or (lambda: False),
                                  inactive or (lambda: None))
        finally:
            self.contacts = None
        if not outcome.ok:
            self.output.halt(outcome.kind)
        return outcome

    def _blocking(self):
        """The active safety conditions that stop this run."""
        return self.safety.terminal if self.contacts is not None else self.safety.active

    def _pause(self, now):
        """Why the run pauses this cycle (a takeover, a contact), an Outcome, or None."""
        taken = self.takeover.active() if self.takeover is not None else None
        if taken:
            self.taken = taken
            return taken
        if self.contacts is None:
            return None
        bumps = []
        while self.bumps:               # one consumer: popleft cannot find it empty
            bumps.append(self.bumps.popleft())
        pressed = [reason for reason in self.safety.active if is_contact(reason)]
        decision = self.contacts.decide(bool(bumps or pressed), now, len(bumps), bumps + pressed)
        if decision == PAUSE:
            return 'bumper contact %d (%s): holding' % (self.contacts.count,
                                                        ', '.join(self.safety.active) or 'released')
        if decision:
            return Outcome(SAFETY_STOP, '%s: %s' % (', '.join(self.contacts.sensors) or 'bumper', decision),
                           outcome.CONTACTS)
        return None

    def _resumed(self, behaviour, label, paused):
        """After a pause of ``paused`` s: the takeover's Outcome (on_takeover abort) or None."""
        taken, self.taken = self.taken, None
        if taken and self.takeover.policy == 'abort':
            return Outcome(TAKEN_OVER, '%s (on_takeover abort)' % taken)
        behaviour.resumed(paused)       # paused time is not driving time, its motion not the drive's
        self.log.warn('%s: going on after %.1f s paused%s', label, paused,
                      ' (%s ended)' % taken if taken else '')
        self.output.release()
        return None

    def _drive(self, behaviour, label, wait, cancelled, inactive):
        p, odometry = self.params, self.odometry
        if self._blocking():
            return Outcome(SAFETY_STOP, ', '.join(self._blocking()))
        odom = odometry.wait_fresh(p.odom_timeout, wait)
        if odom is None:
            return Outcome(ODOMETRY_LOST, odometry.describe_missing(p.odom_timeout))
        behaviour.start(odom)
        self.output.release()
        cycle = DriveCycle(behaviour, p if self.grace else None, p.odom_timeout)
        clock = LoopClock(label, self.log, then='the %s ends (its times and odometry are of the old '
                          'clock)' % label)
        rate = clock.rate(p.control_rate)
        paused_at = None
        first = True
        try:
            while True:
                if not first and rate.sleep():
                    return Outcome(FAILED, describe(*clock.last_jump), outcome.CLOCK)
                first = False
                now, age = rospy.get_time(), odometry.age()
                pause = self._pause(now)
                if isinstance(pause, Outcome):
                    return pause
                if pause:
                    stop = self._stopped(cancelled, inactive)
                    if stop:
                        return stop
                    if paused_at is None:
                        paused_at = now
                        self.log.warn('%s: %s', label, pause)
                    if pause != self.taken:
                        self.output.stop()      # a contact: zero (a takeover: nothing)
                    continue
                if paused_at is not None:
                    ended = self._resumed(behaviour, label, now - paused_at)
                    if ended:
                        return ended
                    paused_at = None
                tripped = self.tripped or ', '.join(self._blocking())
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
                    continue
                command = behaviour.step(odom, now)
                if isinstance(command, Outcome):
                    return command
                self.output.publish(*command)
        except rospy.ROSInterruptException:
            return Outcome(CANCELLED, 'node shutdown')

    def _stopped(self, cancelled, inactive):
        """During a pause: the Outcome of a cancel, the mission leaving, a terminal event."""
        tripped = self.tripped or ', '.join(self._blocking())
        if tripped:
            return Outcome(SAFETY_STOP, tripped)
        if cancelled() or rospy.is_shutdown():
            return Outcome(CANCELLED, 'cancelled')
        why = inactive()
        return Outcome(PREEMPTED, why) if why else None

    def _lost(self, outcome):
        """The odometry outcome, saying what is missing."""
        missing = self.odometry.describe_missing(self.params.odom_timeout)
        return outcome._replace(reason='%s (%s)' % (outcome.reason, missing)
                                if self.grace else missing)

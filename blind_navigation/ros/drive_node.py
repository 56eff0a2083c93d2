"""The one loop of a node that drives (rotate_pi, back_travel_server, calibrate_gyro): a
core/mission_drive drive stepped at ``control_rate`` as core/mission.Mission steps it (events,
cancel, pauses, odometry grace) on a ros/motion.MotionOutput; every end but success halts it.
"""
import threading
from collections import deque

import rospy

from blind_navigation.core import drive, outcome
from blind_navigation.core.allowance import ABORT, DRIVE, HOLD
from blind_navigation.core.mission import Inputs
from blind_navigation.core.mission_drive import DONE, FAILED, ZERO, Pauses
from blind_navigation.core.safety import is_contact
from blind_navigation.ros.clock import LoopClock, describe
from blind_navigation.ros.common import shutting_down
from blind_navigation.ros.motion import MotionOutput


class DriveNode(object):
    """Steps one drive at a time for ``role`` (a ros/layer.Role) on :attr:`output`, clamped to
    ``limits`` (max_v, max_w); ``mission``: the state gating it (None: no takeover watch either);
    ``contacts``: a bumper press pauses the drive (else ends it); ``label()``: its name in logs."""

    def __init__(self, role, limits, mission, contacts, label):
        layer, self.params, self.log, role = role.layer, role.params, role.log, role.ROLE
        self.odometry, self.safety = layer.odometry, layer.safety
        self.role, self.contacts, self.label = role, contacts, label
        self.takeover = layer.takeover(self.params) if mission is not None else None
        self.output = MotionOutput(role, *limits, mission=mission, safety=layer.safety, takeover=self.takeover)
        self.wake = threading.Event()       # set when the node has something to drive
        self.bumps = deque()                # bumper presses (reasons) since the last cycle
        self.drive = self.pauses = self.now = self.clock = self.tripped = None
        layer.safety.on_trip(layer.guard(role)(self._on_trip))
        rospy.on_shutdown(self.wake.set)

    def _on_trip(self, reason):
        if self.contacts and is_contact(reason):
            self.bumps.append(reason)       # a press between two cycles counts too
        else:
            self.tripped = reason           # ends the drive, even if released by the next cycle

    def diagnose(self, stat):
        """The safety conditions active and the takeover, for the role's status."""
        if self.safety.active:
            stat.add('safety', ', '.join(self.safety.active))
        stat.add('takeover', self.takeover.active() or 'none')

    def ticks(self, busy=lambda: True):
        """(now, s the ROS time moved back) at control_rate while ``busy()``, else waiting for
        :attr:`wake`; until shutdown."""
        self.clock = LoopClock(self.role, self.log, then='the drive under way ends (its times and '
                               'odometry are of the old clock)')
        rate = self.clock.rate(self.params.control_rate)
        while not shutting_down():
            if not busy():
                self.wake.wait()
                self.wake.clear()
                continue
            try:
                jump = rate.sleep()
            except rospy.ROSInterruptException:
                return
            yield self.clock.now(), jump

    def start(self, behaviour):
        """Drive ``behaviour`` (TurnDrive, ReturnDrive) from the next :meth:`step` on."""
        self.drive, self.pauses = behaviour, Pauses(self.params, contacts=self.contacts)
        self.bumps.clear()
        self.tripped = None
        self.output.release()

    def feed(self, cycle):
        """core/mission's feed: (decision, odometry stamped now, message)."""
        age = self.odometry.age()
        decision, message = cycle.decide(self.now, None if age is None else self.now - age)
        ended = isinstance(decision, drive.Outcome)
        if message:
            (self.log.error if ended else self.log.warn)('%s: %s', self.label(), message)
        if ended:
            return ABORT, None, '%s (%s)' % (decision.reason, self.odometry.describe_missing(
                self.params.odom_timeout))
        odom = None if decision == HOLD else self.odometry.fresh(self.params.odom_timeout)
        return (HOLD, None, message) if odom is None else (DRIVE, odom, message)

    def step(self, now, jump=0.0, cancelled=False, inactive=None, next_goal=False):
        """One cycle at ``now``: None while the drive goes on, else the Outcome that ended it."""
        self.now = now
        ended = self._interrupted(jump, cancelled, inactive)
        if ended is None:
            bumps = tuple(self.bumps.popleft() for _ in range(len(self.bumps)))
            pressed = bumps + tuple(reason for reason in self.safety.active if is_contact(reason))
            latest = self.odometry.latest()
            operator = self.takeover.active() if self.takeover is not None else None
            paused = self.pauses.cycle(now, pressed, operator, lambda: None if latest is None
                                       else [latest.x, latest.y], self.drive)
            if isinstance(paused, outcome.Ending):
                ended = drive.Outcome(drive.TAKEN_OVER if paused.code == outcome.TAKEOVER else
                                      drive.SAFETY_STOP, paused.reason, paused.code)
            elif paused is not False:
                if paused == ZERO:
                    self.output.stop()      # a contact (a takeover: nothing)
                return None
        if ended is None:
            command = self.drive.step(now, Inputs(next_goal=next_goal))
            if self.drive.phase == FAILED:
                ended = drive.Outcome(drive.FAILED, self.drive.reason, self.drive.code)
            else:
                self.output.contact_over()  # a contact's halt ends once none is active
                self.output.publish(*command)
                return drive.Outcome(drive.SUCCEEDED, '') if self.drive.phase == DONE else None
        self.output.halt(ended.kind)
        return ended

    def _interrupted(self, jump, cancelled, inactive):
        """The Outcome of the time moving back, a Kobuki event, a cancel or the mission leaving."""
        tripped = [self.tripped] if self.tripped else \
            self.safety.terminal if self.contacts else self.safety.active
        if jump:
            return drive.Outcome(drive.FAILED, describe(*self.clock.last_jump), outcome.CLOCK)
        if tripped:
            return drive.Outcome(drive.SAFETY_STOP, 'safety stop: ' + ', '.join(tripped))
        if cancelled or rospy.is_shutdown():
            return drive.Outcome(drive.CANCELLED, 'cancelled')
        return drive.Outcome(drive.PREEMPTED, inactive) if inactive else None

"""rotate_pi: after vision loss, turn the robot by pi on odometry yaw (paper 3.4).

In ``rotating`` it waits for the heading correction, ``recording_end`` and the ``final``
sample, then runs core/rotation.Rotation on a DriveLoop and publishes
``blind_navigation/rotation_done`` (true, or false on a failed turn). Restarted while the
mission rotates, it reports false at once (docs/back_travel.md).
"""
import threading

import rospy
from std_msgs.msg import Bool, Empty

from blind_navigation import names
from blind_navigation.core import drive, mission_state
from blind_navigation.core.allowance import OdomGrace
from blind_navigation.core.gyro_bias import standstill_timeout
from blind_navigation.core.role_params import ROTATE_PI
from blind_navigation.core.rotation import Rotation
from blind_navigation.msg import PathSample
from blind_navigation.ros import diagnostics
from blind_navigation.ros.clock import LoopClock
from blind_navigation.ros.common import shutting_down, subscribe
from blind_navigation.ros.drive_loop import DriveLoop
from blind_navigation.ros.motion import MotionOutput
from blind_navigation.ros.sampling_publisher import FINAL

#: What a wait before the turn does when the ROS time moves back.
NO_TURN = 'no pi turn: its times and odometry are of the old clock'


class RotatePi(object):
    """Turns by ``angle`` when vision is lost (module docstring)."""

    ROLE = mission_state.ROTATION_ROLE
    SCHEMA = ROTATE_PI

    def __init__(self, layer):
        p = self.params = layer.params(self.ROLE, self.SCHEMA)
        self.log = layer.logger(self.ROLE)
        if p.control_rate <= 0 or p.recording_end_timeout < 0 or p.correction_margin < 0:
            raise ValueError('~control_rate must be positive, ~recording_end_timeout and '
                             '~correction_margin not negative')
        Rotation(p)  # validates the rotation params now, not at the first vision loss
        OdomGrace(p)
        self.correction_timeout = standstill_timeout(p) + p.correction_margin
        self.layer = layer
        self.takeover = layer.takeover(p)
        self.output = MotionOutput(self.ROLE, 0.0, p.max_w, layer.mission, layer.safety,
                                   self.takeover)
        self.drive = DriveLoop(self.output, layer.odometry, layer.safety, p, self.log,
                               layer.guard(self.ROLE), takeover=self.takeover)
        self.correction = layer.heading_correction() if p.wait_for_heading_correction else None
        self._trigger = threading.Event()
        self._recording_ended = threading.Event()
        self._turn_begins = threading.Event()
        self.done_pub = rospy.Publisher(names.ROTATION_DONE, Bool, queue_size=1, latch=True)
        guard = layer.guard(self.ROLE)
        subscribe(names.SAMPLE, PathSample, guard(self._on_sample), queue_size=10)
        subscribe(names.RECORDING_END, Empty, guard(lambda _msg: self._turn_begins.set()),
                  queue_size=1)
        self.status = 'waiting for vision loss'
        layer.mission.on_change(guard(self._on_state))
        layer.mission.on_new_mission(guard(self._new_mission))
        layer.diagnostics.add('pi turn', self._diagnose)

    def _diagnose(self, stat):
        failed = self.status.startswith('failed')
        stat.summary(diagnostics.ERROR if failed else diagnostics.OK, self.status)
        if self.correction is not None:
            stat.add('heading correction', 'installed' if self.correction.received else 'awaited')
        if self.layer.safety.active:
            stat.add('safety', ', '.join(self.layer.safety.active))
        stat.add('takeover', self.takeover.active() or 'none')

    # --- events ----------------------------------------------------------------------------------
    def _on_sample(self, msg):
        if msg.command == FINAL:
            self._recording_ended.set()

    def _new_mission(self):
        self._recording_ended.clear()      # the new recording's final sample is awaited
        self._turn_begins.clear()          # and the owner's commit of its turn
        self.status = 'waiting for vision loss'

    def _on_state(self, old, new):
        if new != mission_state.ROTATING:
            return
        if old is None:
            self.log.error('started while the mission is already rotating: how far the robot '
                           'turned is unknown; reporting the turn as failed')
            self.done_pub.publish(Bool(data=False))
            return
        self._trigger.set()

    @property
    def rotating(self):
        return self.layer.mission.state == mission_state.ROTATING

    # --- the turn --------------------------------------------------------------------------------
    def run(self):
        """Wait for the mission to rotate, turn, report (blocks until shutdown)."""
        rospy.on_shutdown(self._trigger.set)
        while True:
            self._trigger.wait()        # the mission rotates, or shutdown
            if shutting_down():
                return
            self._trigger.clear()
            if not self.rotating:       # it left rotating before this thread woke
                continue
            self.layer.odometry.acquire(self.ROLE)
            self.status = 'turning'
            try:
                ok = self._wait_for_heading_correction() and self._wait_for_recording_end() \
                    and self.rotate()
            finally:
                self.output.halt('turn over')
                self.layer.odometry.release(self.ROLE)
            back = self.layer.mission.state == mission_state.RECORDING
            self.status = 'turned' if ok else 'waiting for vision loss (vision came back)' if back \
                else 'failed (see the log)'
            if self.rotating:
                self.done_pub.publish(Bool(data=ok))
            self.layer.diagnostics.now()

    def _wait_for_recording_end(self):
        """Until the owner ends the recording (False: the mission left rotating first), then
        until the recorder's final sample or ``recording_end_timeout`` (sim) passes. False
        too if the ROS time moves back meanwhile."""
        clock = LoopClock('waiting for the end of the recording', self.log, then=NO_TURN)
        try:
            while not self._turn_begins.is_set():
                if rospy.is_shutdown() or not self.rotating or clock.sleep(0.01):
                    return False
            deadline = rospy.get_time() + self.params.recording_end_timeout
            while not self._recording_ended.is_set() and rospy.get_time() < deadline:
                if rospy.is_shutdown() or not self.rotating or clock.sleep(0.01):
                    return False
        except rospy.ROSInterruptException:
            return False
        if not self._recording_ended.is_set():
            self.log.warn('no final sample from the recorder within %.1f s; turning anyway',
                          self.params.recording_end_timeout)
        return True

    def _wait_for_heading_correction(self):
        """True once the heading correction is installed in the odometry (or none is
        awaited); False after ``correction_timeout`` s of sim time, at shutdown, when
        the mission left rotating or the ROS time moved back. Commands nothing meanwhile."""
        if self.correction is None or self.correction.received:
            return True
        clock = LoopClock('waiting for the heading correction', self.log, then=NO_TURN)
        self.log.info('standing still while heading_correction measures the gyro bias (waiting '
                      'at most %.0f s for %s)', self.correction_timeout,
                      rospy.resolve_name(names.HEADING_CORRECTION))
        deadline = rospy.get_time() + self.correction_timeout - self.takeover.paused()
        try:
            while not self.correction.received:
                if rospy.is_shutdown() or not self.rotating:
                    return False
                if rospy.get_time() >= deadline + self.takeover.paused():   # takeovers do not count
                    self.log.error('cannot turn: no heading correction on %s within %.0f s (is '
                                   'heading_correction running?); the robot stays here',
                                   rospy.resolve_name(names.HEADING_CORRECTION),
                                   self.correction_timeout)
                    return False
                if clock.sleep(0.02):
                    return False
        except rospy.ROSInterruptException:
            return False
        return True

    def rotate(self):
        """Run one rotation; True on success. Always ends with zero velocity."""
        turn = _Turn(Rotation(self.params), self.log)
        outcome = self.drive.run(turn, 'turn', wait=self.params.odom_grace, inactive=self._inactive)
        if outcome.kind == drive.SAFETY_STOP:
            self.log.error('%s: safety stop: %s', 'turn stopped' if turn.started else 'cannot turn',
                           outcome.reason)
        elif outcome.kind == drive.ODOMETRY_LOST and not turn.started:
            self.log.error('cannot turn: %s', outcome.reason)
        return outcome.ok

    def _inactive(self):
        return None if self.rotating else 'the mission left rotating'


class _Turn(drive.Behaviour):
    """The pi turn as a drive-loop behaviour: core/rotation.Rotation until done or failed."""

    def __init__(self, rotation, log):
        self.rotation, self.log, self.started = rotation, log, False

    def start(self, odom):
        self.log.info('turning by %.3f rad from yaw %.3f', self.rotation.angle, odom.yaw)
        self.rotation.start(odom)
        self.started = True

    def hold(self, seconds):
        self.rotation.hold(seconds)

    def step(self, odom, now):
        r = self.rotation
        command = r.step(odom)
        if r.failed:
            self.log.error('turn failed: %.3f of %.3f rad after the %.0f s allowance',
                           r.turned, r.angle, r.time_allowance)
            return drive.Outcome(drive.TIMED_OUT, 'time allowance spent')
        if r.done:
            self.log.info('turned %.4f rad (tolerance %.3f)', r.turned, r.tolerance)
            return drive.Outcome(drive.SUCCEEDED, '')
        return command

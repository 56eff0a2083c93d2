"""rotate_pi (paper 3.4): in ``rotating``, after the heading correction, ``recording_end`` and
the ``final`` sample, the mission's TurnDrive on a DriveNode; ``rotation_done`` true or false
(false at once when restarted while rotating; docs/back_travel.md).
"""
import math
import types

import rospy
from std_msgs.msg import Bool, Empty

from blind_navigation import names
from blind_navigation.core import drive, mission_state
from blind_navigation.core.allowance import OdomGrace
from blind_navigation.core.gyro_bias import standstill_timeout
from blind_navigation.core.mission_drive import TurnDrive
from blind_navigation.core.mission_limits import PausedClock
from blind_navigation.core.role_params import ROTATE_PI
from blind_navigation.core.rotation import Rotation
from blind_navigation.msg import PathSample
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.drive_node import DriveNode
from blind_navigation.ros.mission import Role
from blind_navigation.ros.sampling_publisher import FINAL


class RotatePi(Role):
    """Turns by ``angle`` when vision is lost (module docstring)."""

    ROLE = mission_state.ROTATION_ROLE
    SCHEMA = ROTATE_PI

    def __init__(self, layer):
        Role.__init__(self, layer)
        p = self.params
        Rotation(p), OdomGrace(p)   # validates the rotation's and the odometry's params now
        self.correction_timeout = standstill_timeout(p) + p.correction_margin
        # the mission's turn without its own checks: the client times and checks the turn
        self.config = types.SimpleNamespace(turn_tolerance=math.pi, standstill=p, limits=None,
                                            vision_back_grace=0.0)
        self.driver = DriveNode(self, (0.0, p.max_w), layer.mission, False, lambda: 'turn')
        self.output, self.takeover = self.driver.output, self.driver.takeover
        self.correction = layer.heading_correction() if p.wait_for_heading_correction else None
        self.topic = rospy.resolve_name(names.HEADING_CORRECTION)
        self.trigger = self.final = self.turn_begins = False   # rotating; the final sample; recording_end
        self.waiting = self.paused = None   # the wait before the turn (_ready's since); takeovers then
        self.done_pub = rospy.Publisher(names.ROTATION_DONE, Bool, queue_size=1, latch=True)
        subscribe(names.SAMPLE, PathSample, self.guard(self._on_sample), queue_size=10)
        subscribe(names.RECORDING_END, Empty, self.guard(self._on_recording_end), queue_size=1)
        self.status = 'waiting for vision loss'
        self.follow('pi turn')

    def _diagnose(self, stat):
        stat.summary(diagnostics.ERROR if self.status.startswith('failed') else diagnostics.OK, self.status)
        if self.correction is not None:
            stat.add('heading correction', 'installed' if self.correction.received else 'awaited')
        self.driver.diagnose(stat)

    def _on_sample(self, msg):
        if msg.command == FINAL:
            self.final = True

    def _on_recording_end(self, _msg):
        self.turn_begins = True

    def _new_mission(self):
        self.final = self.turn_begins = False   # the new recording's final sample, turn awaited
        self.status = 'waiting for vision loss'

    def _on_state(self, old, new):
        if new != mission_state.ROTATING:
            return
        if old is None:
            self.log.error('started while the mission is already rotating: how far the robot '
                           'turned is unknown; reporting the turn as failed')
            self.done_pub.publish(Bool(data=False))
            return
        self.trigger = True
        self.driver.wake.set()

    @property
    def rotating(self):
        return self.layer.mission.state == mission_state.ROTATING

    def run(self):
        """Wait for the mission to rotate, turn, report (ros/layer.run_roles)."""
        for now, jump in self.driver.ticks(lambda: self.trigger or self.waiting is not None or
                                           self.driver.drive is not None):
            self._cycle(now, jump)

    def _cycle(self, now, jump):
        if self.waiting is None and self.driver.drive is None:     # the mission rotates
            self.trigger = False
            if not self.rotating:
                return
            self.layer.odometry.acquire(self.ROLE)
            self.status, self.waiting, self.paused = 'turning', [now, None, None], self.takeover.paused()
            if self.correction is not None and not self.correction.received:
                self.log.info('standing still while heading_correction measures the gyro bias (waiting at '
                              'most %.0f s for %s)', self.correction_timeout, self.topic)
        if self.driver.drive is None:
            ready = self._ready(now, jump, self.waiting)
            if ready is False:
                self._finish(False)
            elif ready is not None:
                self.waiting, self.driver.now = None, now
                turn = TurnDrive(self.params, self.driver.feed, ready, self.config, PausedClock(now))
                self.driver.start(turn)
                self.log.info('turning by %.3f rad from yaw %.3f', turn.rotation.angle, ready.yaw)
            return
        ended = self.driver.step(now, jump, inactive=None if self.rotating else 'the mission left rotating')
        if ended is not None:
            rotation = self.driver.drive.rotation
            if ended.ok:
                self.log.info('turned %.4f rad (tolerance %.3f)', rotation.turned, rotation.tolerance)
            else:
                (self.log.info if ended.kind == drive.PREEMPTED else self.log.error)(
                    'turn stopped after %.3f of %.3f rad: %s', rotation.turned, rotation.angle, ended.reason)
            self._finish(ended.ok)

    def _ready(self, now, jump, since):
        """Before the turn (``since``: when the mission rotated, recording_end came, the turn could
        begin): None while waiting, False if it cannot turn, else the fresh odometry to turn from."""
        p = self.params
        if jump or not self.rotating:
            return False
        if self.correction is not None and not self.correction.received:
            if now - since[0] - (self.takeover.paused() - self.paused) < self.correction_timeout:
                return None
            self.log.error('cannot turn: no heading correction on %s within %.0f s (is heading_correction '
                           'running?); the robot stays here', self.topic, self.correction_timeout)
            return False
        if not self.turn_begins:
            return None
        since[1] = now if since[1] is None else since[1]
        if since[2] is None and not self.final and now - since[1] < p.recording_end_timeout:
            return None
        if since[2] is None and not self.final:
            self.log.warn('no final sample from the recorder within %.1f s; turning anyway',
                          p.recording_end_timeout)
        since[2] = now if since[2] is None else since[2]
        odom = self.layer.odometry.fresh(p.odom_timeout)
        if odom is None and now - since[2] < p.odom_grace:
            return None
        if odom is None:
            self.log.error('cannot turn: %s', self.layer.odometry.describe_missing(p.odom_timeout))
        return odom or False

    def _finish(self, ok):
        """The turn (or its wait) ended: zero, the odometry released, ``rotation_done``."""
        self.output.halt('turn over')
        self.layer.odometry.release(self.ROLE)
        self.waiting = self.driver.drive = None
        back = self.layer.mission.state == mission_state.RECORDING
        self.status = 'turned' if ok else 'waiting for vision loss (vision came back)' if back \
            else 'failed (see the log)'
        if self.rotating:
            self.done_pub.publish(Bool(data=ok))
        self.layer.diagnostics.now()

"""rotate_pi: after vision loss, turn the robot by pi on odometry yaw (paper 3.4).

On /blind_navigation/vision_lost (std_msgs/Empty), while the mission state is
``recording`` (or already ``rotating``), runs core/rotation.Rotation in closed
loop on odometry, publishing on ``cmd_vel_topic``; then publishes
std_msgs/Bool on /blind_navigation/rotation_done: true when turned within the
tolerance, false on failure (time allowance, odometry older than
``odom_timeout``, a Kobuki bumper/cliff/wheel-drop event). Zero velocity on
failure and shutdown; a safety event halts the output from its callback at
once, and no turn starts while a sensor is active.

The turn waits for the recorder's ``final`` sample (at most
``recording_end_timeout``), so the last landmark is taken before the robot
turns: `rostopic pub -1` reaches each subscriber at its own moment, and a turn
that started first would be recorded as part of the path.

With ``wait_for_heading_correction`` (blind_navigation.launch sets it with
``heading_correction``) it then stands still until heading_correction has
published the latched /blind_navigation/heading_correction (it measures the
gyro bias on the standing robot after vision loss, at most ``standstill_time``) and
``CORRECTED_MESSAGES`` odometry messages arrived after it (heading_correction
relays the first corrected one before it publishes the correction, so this
holds unless the odometry connection lags that many messages), at most
``correction_timeout`` s of sim time; none by then: no turn, rotation_done
false (the robot stays where it is).
"""
import threading

import rospy
from std_msgs.msg import Bool, Empty, String

from blind_navigation import names
from blind_navigation.msg import HeadingCorrection, PathSample

from blind_navigation.ros.back_travel_common import LatestOdom, SafetyMonitor, VelocityOutput
from blind_navigation.core import mission_state as state
from blind_navigation.core.gyro_bias import standstill_timeout
from blind_navigation.core.rotation import ROTATION_DEFAULTS, Rotation
from blind_navigation.ros.landmark_saving import FINAL
from blind_navigation.ros.common import load_params

ACCEPTING_STATES = (state.RECORDING, state.ROTATING)
#: Odometry messages that must arrive after the heading correction before the turn starts
#: on them (they are in the corrected frame; counted, not compared by stamp, so a clock
#: offset between the odometry's source and this node cannot stall the turn).
CORRECTED_MESSAGES = 3


class RotatePi(object):
    """Turns by ``angle`` when vision is lost.

    Params (DEFAULTS): ``cmd_vel_topic`` ('/cmd_vel_mux/input/teleop'),
    ``odom_topic`` ('/odom'), ``control_rate`` (Hz, 50), ``odom_timeout``
    (s, 0.4), ``bumper_topic`` / ``cliff_topic`` / ``wheel_drop_topic``
    (Kobuki's /mobile_base/events/*), and core/rotation.py's ROTATION_DEFAULTS: ``angle`` (pi rad),
    ``max_w`` (0.6 rad/s, also the output clamp; linear velocity is clamped
    to 0), ``min_w`` (0.08 rad/s), ``gain`` (1.5 1/s), ``decel`` (0.5 rad/s^2),
    ``tolerance`` (0.01 rad), ``settle_w`` (0.02 rad/s), ``time_allowance`` (30 s);
    ``recording_end_timeout`` (s, 1.0): longest wait for the recorder's final sample;
    ``wait_for_heading_correction`` (false): before turning, wait for heading_correction's
    latched result and the corrected odometry after it, at most ``correction_timeout``
    (s of sim time; default 2 x STANDSTILL_DEFAULTS' standstill_time + 30 = 270 s, 25 s above
    heading_correction's default standstill timeout, 2 x standstill_time + 5 s).
    """

    DEFAULTS = dict(ROTATION_DEFAULTS, cmd_vel_topic='/cmd_vel_mux/input/teleop', odom_topic='/odom',
                    control_rate=50.0, odom_timeout=0.4, recording_end_timeout=1.0,
                    wait_for_heading_correction=False,
                    correction_timeout=standstill_timeout() + 25.0,
                    **{kind + '_topic': topic for kind, topic in names.SAFETY_EVENTS.items()})

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        if p.control_rate <= 0 or p.odom_timeout <= 0 or p.recording_end_timeout < 0 \
                or p.correction_timeout <= 0:
            raise ValueError('~control_rate, ~odom_timeout and ~correction_timeout must be '
                             'positive, ~recording_end_timeout not negative')
        Rotation(p)  # validates the rotation params now, not at the first vision loss
        self.output = VelocityOutput(p.cmd_vel_topic, 0.0, p.max_w)
        self._odom_count = 0         # odometry messages received
        self._correction_at = None   # self._odom_count when the heading correction arrived
        self.odom = LatestOdom(p.odom_topic, self._on_odom_state)
        self.mission_state = None
        self._trigger = threading.Event()
        self._busy = False
        self._tripped = None
        self._recording_ended = threading.Event()
        self.safety = SafetyMonitor({kind: getattr(p, kind + '_topic') for kind in names.SAFETY_EVENTS},
                                    self._on_trip)
        self.done_pub = rospy.Publisher(names.ROTATION_DONE, Bool, queue_size=1)
        rospy.Subscriber(names.STATE, String, self._on_state, queue_size=5)
        rospy.Subscriber(names.VISION_LOST, Empty, self._on_vision_lost, queue_size=1)
        rospy.Subscriber(names.SAMPLE, PathSample, self._on_sample, queue_size=10)
        if p.wait_for_heading_correction:
            rospy.Subscriber(names.HEADING_CORRECTION, HeadingCorrection, self._on_correction,
                             queue_size=1)

    def _on_odom_state(self, _odom, _msg):
        self._odom_count += 1

    def _on_correction(self, _msg):
        if self._correction_at is None:
            self._correction_at = self._odom_count

    def _on_state(self, msg):
        self.mission_state = msg.data

    def _on_sample(self, msg):
        if msg.command == FINAL:
            self._recording_ended.set()

    def _wait_for_recording_end(self):
        """Until the recorder's final sample is seen or ``recording_end_timeout`` (sim) passes."""
        deadline = rospy.Time.now() + rospy.Duration(self.params.recording_end_timeout)
        while not self._recording_ended.is_set() and rospy.Time.now() < deadline:
            if rospy.is_shutdown():
                return
            rospy.sleep(0.01)
        if not self._recording_ended.is_set():
            rospy.logwarn('%s: no final sample from the recorder within %.1f s; turning anyway',
                          rospy.get_name(), self.params.recording_end_timeout)

    def _corrected_odometry_ready(self):
        at = self._correction_at
        return at is not None and self._odom_count - at >= CORRECTED_MESSAGES

    def _wait_for_heading_correction(self):
        """With ``wait_for_heading_correction``: True once heading_correction's result is
        in and ``CORRECTED_MESSAGES`` odometry messages after it arrived, False after
        ``correction_timeout`` s of sim time or at shutdown. Commands nothing meanwhile."""
        p = self.params
        if not p.wait_for_heading_correction or self._corrected_odometry_ready():
            return True
        if self._correction_at is None:
            rospy.loginfo('%s: standing still while heading_correction measures the gyro bias '
                          '(waiting at most %.0f s for %s)', rospy.get_name(), p.correction_timeout,
                          names.HEADING_CORRECTION)
        deadline = rospy.get_time() + p.correction_timeout
        try:
            while not self._corrected_odometry_ready():
                if rospy.is_shutdown():
                    return False
                if rospy.get_time() >= deadline:
                    break
                rospy.sleep(0.02)
        except rospy.ROSInterruptException:
            return False
        if self._corrected_odometry_ready():
            return True
        if self._correction_at is None:
            rospy.logerr('%s: cannot turn: no heading correction on %s within %.0f s (is '
                         'heading_correction running?); the robot stays here', rospy.get_name(),
                         names.HEADING_CORRECTION, p.correction_timeout)
        else:
            rospy.logerr('%s: cannot turn: no odometry on %s after the heading correction within '
                         '%.0f s; the robot stays here', rospy.get_name(), p.odom_topic,
                         p.correction_timeout)
        return False

    def _on_trip(self, reason):
        if self._busy:
            self._tripped = reason
            self.output.halt('safety: ' + reason)

    def _on_vision_lost(self, _msg):
        if self._busy:
            return
        if self.mission_state not in ACCEPTING_STATES:
            rospy.logwarn('%s: vision_lost ignored: mission state is %r (turns only while %s)',
                          rospy.get_name(), self.mission_state, ' or '.join(ACCEPTING_STATES))
            return
        self._busy = True
        self._trigger.set()

    def spin(self):
        while not rospy.is_shutdown():
            if self._trigger.wait(0.2):
                self._trigger.clear()
                self._wait_for_recording_end()
                if self._wait_for_heading_correction():
                    ok = self.rotate()
                else:
                    ok = False
                    self.output.halt('no heading correction')
                self.done_pub.publish(Bool(data=ok))
                self._busy = False

    def rotate(self):
        """Run one rotation; True on success. Always ends with zero velocity."""
        p = self.params
        rotation = Rotation(p)
        self._tripped = None
        if self.safety.active:
            rospy.logerr('%s: cannot turn: safety stop: %s', rospy.get_name(),
                         ', '.join(self.safety.active))
            return False
        odom = self.odom.fresh(p.odom_timeout)
        if odom is None:
            rospy.logerr('%s: cannot turn: %s', rospy.get_name(), self.odom.describe_missing(p.odom_timeout))
            return False
        rospy.loginfo('%s: turning by %.3f rad from yaw %.3f', rospy.get_name(), rotation.angle, odom.yaw)
        rotation.start(odom)
        rate = rospy.Rate(p.control_rate)
        self.output.release()
        try:
            while not rospy.is_shutdown():
                if self._tripped:
                    rospy.logerr('%s: turn stopped: safety stop: %s', rospy.get_name(), self._tripped)
                    return False
                odom = self.odom.fresh(p.odom_timeout)
                if odom is None:
                    rospy.logerr('%s: turn stopped: %s', rospy.get_name(),
                                 self.odom.describe_missing(p.odom_timeout))
                    return False
                v, w = rotation.step(odom)
                if rotation.done or rotation.failed:
                    break
                self.output.publish(v, w)
                rate.sleep()
        except rospy.ROSInterruptException:
            return False
        finally:
            self.output.halt('turn over')
        if rotation.failed:
            rospy.logerr('%s: turn failed: %.3f of %.3f rad after the %.0f s allowance',
                         rospy.get_name(), rotation.turned, rotation.angle, rotation.time_allowance)
        elif rotation.done:
            rospy.loginfo('%s: turned %.4f rad (tolerance %.3f)', rospy.get_name(), rotation.turned,
                          rotation.tolerance)
        return rotation.done

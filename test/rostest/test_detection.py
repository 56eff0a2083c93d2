#!/usr/bin/env python3
"""rostest (detection.test; fake_turtlebot.test runs its case after its own):
vision_monitor detects each vision failure mode once, within its latency, and
ignores a flicker shorter than its debounce.

~scenarios maps each failure mode to its run: {mode: {ns, flicker, monitors,
blind_monitors, quiet_after}} (monitor nodes named in ``ns``); every scenario runs at once, on one clock, against
the monitors of its namespace ``ns`` (sensor topics and the manual vision_lost
under it), and each is one TestCase. With ~source ``own`` (default) this node is
its own small sensor rig under sim time: it publishes /clock (100 Hz ticks of 10
ms at real-time factor ~rtf) and, per scenario, a 20 Hz camera (sensor_msgs/Image rgb8) with its sensor_msgs/CameraInfo (what the
camera-stall detector watches unless the ``dark`` detector makes the monitor read the
images), RTAB-Map-like visual odometry
(nav_msgs/Odometry with RTAB-Map's lost convention) and RTAB-Map-like odom_info
(a runtime-generated rtabmap_msgs/OdomInfo, so no rtabmap package is needed).
With ~source ``fake_turtlebot`` the sensors are launch/fake_turtlebot.launch's,
failed and restored through /fake_turtlebot/set_vision (one scenario, ns ''). The
mode picks what fails: ``dark`` (images black, VO lost), ``stall`` (camera and VO stop),
``lost`` (camera fine, VO lost), ``manual`` (this node publishes
<ns>/blind_navigation/vision_lost by hand, then camera and VO stop: the monitor
must report ``manual`` and never add a vision_lost of its own). ``monitors`` maps
each vision_monitor node under test to [its vision_lost topic, the detector
expected to fire or ``any``]; ``blind_monitors`` maps monitors whose topics nobody
publishes (a robot without a camera) to their vision_lost topic: they must stay
quiet all along and warn that their detectors are not armed.
"""
import sys
import threading
import time
import unittest

import numpy
import rosgraph
import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock, Log
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Empty, String
from std_srvs.srv import SetBool

from blind_navigation.ros.vision_monitor import VisionMonitor
from blind_navigation.sim.odom_info import OdomInfo

import waiting  # noqa: F401 (a class fixture's error keeps its message)

TICK = 0.01             # sim seconds per /clock message
SENSOR_EVERY = 5        # ticks between sensor messages: 20 Hz
LATENCY_MARGIN = 0.2    # issue 6: within the detector's timeout + debounce + 0.2 s
WALL_TIMEOUT = 30.0     # s, any wait in this test
QUIET_AFTER = 1.5       # sim s watched after the loss for a second message
FAILS = {  # mode: (camera, vo) in failure: 'ok' | 'dark' | 'lost' | None (silent)
    'dark': ('dark', 'lost'),
    'stall': (None, None),
    'lost': ('ok', 'lost'),
    'manual': (None, None),
}
CAN_FIRE = {'dark': {'dark', 'vo_lost', 'odom_info'}, 'stall': {'stall', 'vo_stall'},
            'lost': {'vo_lost', 'odom_info'}, 'manual': {'manual'}}


class SensorRig(object):
    """What the scenario needs from the sensors: ``now`` (sim s), ``set_failed``, ``wait_until``."""

    def wait_until(self, sim_time, why):
        deadline = time.time() + WALL_TIMEOUT
        while self.now < sim_time:
            if time.time() > deadline or rospy.is_shutdown():
                raise AssertionError('sim time did not reach %.2f s (%s) within %.0f s wall'
                                     % (sim_time, why, WALL_TIMEOUT))
            time.sleep(0.01)


class OwnClock(object):
    """/clock at ``rtf`` x real time in a thread; every SENSOR_EVERY ticks, each channel
    (:class:`OwnSensors`) publishes its sensors."""

    def __init__(self, rtf):
        self.rtf = rtf
        self.now = 0.0
        self.ticks = 0
        self.lock = threading.Lock()
        self.channels = []
        self.clock_pub = rospy.Publisher('/clock', Clock, queue_size=10)
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.thread.start()

    def run(self):
        start = time.time()
        while not rospy.is_shutdown():
            with self.lock:
                self.ticks += 1
                self.now = self.ticks * TICK
                ticks, now = self.ticks, self.now
                channels = list(self.channels)
            stamp = rospy.Time.from_sec(now)
            self.clock_pub.publish(Clock(clock=stamp))
            for channel in channels:
                channel.tick(now, stamp, ticks % SENSOR_EVERY == 0)
            time.sleep(max(0.0, start + now / self.rtf - time.time()))


class OwnSensors(SensorRig):
    """One scenario's camera, RTAB-Map VO and odom_info under ``ns``, on ``clock``'s ticks;
    ``failed`` switches them to the failure mode."""

    def __init__(self, mode, clock, ns=''):
        self.camera_fail, self.vo_fail = FAILS[mode]
        self.clock = clock
        self.failed = False
        self.failed_at = None
        self.lock = threading.Lock()
        rng = numpy.random.RandomState(1)
        self.bright = rng.randint(40, 220, size=(48, 64, 3)).astype(numpy.uint8).tobytes()
        self.dark = rng.randint(0, 5, size=(48, 64, 3)).astype(numpy.uint8).tobytes()
        self.image_pub = rospy.Publisher(ns + '/camera/rgb/image_rect_color', Image, queue_size=5)
        self.camera_info_pub = rospy.Publisher(ns + '/camera/rgb/camera_info', CameraInfo, queue_size=5)
        self.vo_pub = rospy.Publisher(ns + '/rtabmap/odom', Odometry, queue_size=5)
        self.info_pub = rospy.Publisher(ns + '/rtabmap/odom_info_lite', OdomInfo, queue_size=5)
        self.sensor_topics = {pub.resolved_name
                              for pub in (self.image_pub, self.camera_info_pub, self.vo_pub,
                                          self.info_pub)}
        with clock.lock:
            clock.channels.append(self)

    @property
    def now(self):
        return self.clock.now

    def set_failed(self, failed):
        """Switch the failure on/off at the next tick; returns that tick's sim time."""
        with self.lock:
            self.failed = failed
            self.failed_at = None
        while not rospy.is_shutdown():
            with self.lock:
                if self.failed_at is not None:
                    return self.failed_at
            time.sleep(0.001)

    def tick(self, now, stamp, sensors):
        """A tick of the clock at ``now`` (s, ``stamp``); ``sensors``: publish them on it."""
        with self.lock:
            if self.failed_at is None:
                self.failed_at = now
            failed = self.failed
        if sensors:
            self.publish_sensors(stamp, failed)

    def publish_sensors(self, stamp, failed):
        camera = self.camera_fail if failed else 'ok'
        vo = self.vo_fail if failed else 'ok'
        if camera is not None:
            image = Image(height=48, width=64, encoding='rgb8', step=64 * 3,
                          data=self.dark if camera == 'dark' else self.bright)
            image.header.stamp = stamp
            self.image_pub.publish(image)
            self.camera_info_pub.publish(CameraInfo(header=image.header, height=image.height,
                                                    width=image.width))
        if vo is not None:
            odom = Odometry()
            odom.header.stamp = stamp
            odom.header.frame_id = 'odom'
            if vo == 'lost':  # RTAB-Map's convention
                odom.pose.covariance = [9999.0 if i % 7 == 0 else 0.0 for i in range(36)]
                odom.twist.covariance = list(odom.pose.covariance)
            else:
                odom.pose.pose.position.x = 0.1 * stamp.to_sec()
                odom.pose.pose.orientation.w = 1.0
                odom.pose.covariance = [0.001 if i % 7 == 0 else 0.0 for i in range(36)]
            info = OdomInfo(lost=(vo == 'lost'), matches=0 if vo == 'lost' else 150)
            info.header.stamp = stamp
            self.vo_pub.publish(odom)
            self.info_pub.publish(info)


class FakeTurtleBotSensors(SensorRig):
    """launch/fake_turtlebot.launch's camera and VO, failed through /fake_turtlebot/set_vision."""

    sensor_topics = {'/camera/rgb/image_rect_color', '/camera/rgb/camera_info', '/rtabmap/odom'}

    def __init__(self, _mode, _clock, _ns=''):
        rospy.wait_for_service('/fake_turtlebot/set_vision', timeout=WALL_TIMEOUT)
        self.set_vision = rospy.ServiceProxy('/fake_turtlebot/set_vision', SetBool)
        rospy.wait_for_message('/camera/rgb/image_rect_color', Image, timeout=WALL_TIMEOUT)

    @property
    def now(self):
        return rospy.Time.now().to_sec()

    def set_failed(self, failed):
        """Fail/restore vision; returns the sim time just before the request (conservative)."""
        before = self.now
        response = self.set_vision(not failed)
        if not response.success:
            raise AssertionError('/fake_turtlebot/set_vision refused: %s' % response.message)
        return before


SOURCES = {'own': OwnSensors, 'fake_turtlebot': FakeTurtleBotSensors}


class Scenario(object):
    """One failure mode against its monitors (a ~scenarios entry): warm up, flicker,
    recover, fail for good; :meth:`run` plays it (in a thread, beside the others)."""

    def __init__(self, mode, config, clock):
        self.mode = mode
        self.ns = config.get('ns', '')
        self.flicker = config['flicker']
        self.monitors = {self.node(name): value for name, value in config['monitors'].items()}
        self.quiet_after = config.get('quiet_after', QUIET_AFTER)
        self.sensors = SOURCES[rospy.get_param('~source', 'own')](mode, clock, self.ns)
        self.received = {name: [] for name in self.monitors}
        self.reasons = {}
        for name, (topic, _expected) in self.monitors.items():
            rospy.Subscriber(topic, Empty, self.on_lost, callback_args=name)
            rospy.Subscriber('/%s/loss' % name, String, self.on_reason, callback_args=name)
        self.blind = {self.node(name): topic for name, topic in config.get('blind_monitors', {}).items()}
        self.blind_received = {name: [] for name in self.blind}
        self.blind_warnings = {name: [] for name in self.blind}
        for name, topic in self.blind.items():
            rospy.Subscriber(topic, Empty, lambda _msg, name=name: self.blind_received[name].append(
                self.sensors.now))
        rospy.Subscriber('/rosout', Log, self.on_log)
        self.error = None

    def node(self, name):
        """The monitor node ``name`` of this scenario's namespace, without the leading slash."""
        return (self.ns.strip('/') + '/' + name).lstrip('/')

    def run(self):
        try:
            self.play()
        except BaseException:       # raised again in the scenario's setUpClass
            self.error = sys.exc_info()

    def play(self):
        sensors = self.sensors
        self.wait_for_monitors()
        sensors.wait_until(sensors.now + 2.0, 'warm-up')
        flicker_at = sensors.set_failed(True)
        sensors.wait_until(flicker_at + self.flicker, 'flicker')
        sensors.set_failed(False)
        sensors.wait_until(sensors.now + 2.0, 'after the flicker')
        self.fired_on_flicker = {name: list(times) for name, times in self.received.items()}
        self.failed_at = sensors.set_failed(True)
        if self.mode == 'manual':
            rospy.Publisher(self.ns + '/blind_navigation/vision_lost', Empty, queue_size=1,
                            latch=True).publish(Empty())
        deadline = time.time() + WALL_TIMEOUT
        while not all(self.received.values()) and time.time() < deadline:
            time.sleep(0.01)
        sensors.wait_until(sensors.now + self.quiet_after, 'watching for a second loss')

    def wait_for_monitors(self):
        """Until every monitor node subscribes to a sensor topic (its detectors exist)."""
        sensor_topics = self.sensors.sensor_topics
        master = rosgraph.Master(rospy.get_name())
        deadline = time.time() + WALL_TIMEOUT
        while time.time() < deadline and not rospy.is_shutdown():
            _publishers, subscribers, _services = master.getSystemState()
            listening = {node.lstrip('/') for topic, nodes in subscribers if topic in sensor_topics
                         for node in nodes}
            if listening >= set(self.monitors):
                return
            time.sleep(0.05)
        raise AssertionError('the vision monitors %s did not subscribe within %.0f s'
                             % (sorted(self.monitors), WALL_TIMEOUT))

    def on_lost(self, _msg, name):
        self.received[name].append(self.sensors.now)

    def on_reason(self, msg, name):
        self.reasons[name] = msg.data

    def on_log(self, msg):
        name = msg.name.lstrip('/')
        if name in self.blind_warnings:
            self.blind_warnings[name].append(msg.msg)


#: Scenario of each mode, once :func:`play_all` ran.
PLAYED = {}


def play_all():
    """Every ~scenarios entry at once on one clock (the fake's with ~source fake_turtlebot)."""
    clock = OwnClock(rospy.get_param('~rtf', 1.0)) if rospy.get_param('~source', 'own') == 'own' else None
    scenarios = [Scenario(mode, config, clock) for mode, config in sorted(rospy.get_param('~scenarios').items())]
    threads = [threading.Thread(target=scenario.run, daemon=True) for scenario in scenarios]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(4 * WALL_TIMEOUT)
    PLAYED.update((scenario.mode, scenario) for scenario in scenarios)


class DetectionTest(unittest.TestCase):
    """One scenario's checks (``mode``: :func:`cases` makes one subclass per scenario); the
    first setUpClass plays them all."""

    mode = None

    @classmethod
    def setUpClass(cls):
        if not PLAYED:
            PLAYED[None] = None         # played once, whatever happens
            play_all()
        scenario = PLAYED.get(cls.mode)
        if scenario is None:
            raise AssertionError('scenario %s was not played (see the first case\'s error)' % cls.mode)
        if scenario.error:
            raise scenario.error[1].with_traceback(scenario.error[2])
        for name in ('flicker', 'monitors', 'received', 'reasons', 'blind', 'blind_received',
                     'blind_warnings', 'fired_on_flicker', 'failed_at'):
            setattr(cls, name, getattr(scenario, name))

    def latency_bound(self, name):
        defaults = VisionMonitor.SCHEMA.make()     # image_timeout: a constant, debounce: a param

        def param(key):
            return rospy.get_param('/%s/%s' % (name, key), getattr(defaults, key))
        timeout = param('image_timeout') if self.mode == 'stall' else 0.0
        return timeout + param('debounce') + LATENCY_MARGIN

    def test_flicker_does_not_fire(self):
        for name, times in self.fired_on_flicker.items():
            self.assertEqual(times, [], '%s fired on a %.1f s %s flicker' % (name, self.flicker, self.mode))

    def test_fires_exactly_once_within_latency(self):
        for name, times in self.received.items():
            self.assertEqual(len(times), 1, '%s: vision_lost at sim %s, expected exactly one after '
                             'the %s failure at %.2f s' % (name, times, self.mode, self.failed_at))
            latency = times[0] - self.failed_at
            rospy.loginfo('detection latency %s %s: %.3f s (bound %.2f s)', self.mode, name,
                          latency, self.latency_bound(name))
            print('LATENCY mode=%s monitor=%s latency=%.3f bound=%.2f'
                  % (self.mode, name, latency, self.latency_bound(name)))
            self.assertGreaterEqual(latency, 0.0)
            self.assertLessEqual(latency, self.latency_bound(name),
                                 '%s: %.3f s from the %s failure to vision_lost' % (name, latency, self.mode))

    def test_monitor_without_sensors_stays_quiet_and_warns(self):
        for name in self.blind:
            self.assertEqual(self.blind_received[name], [],
                             '%s fired although it never saw an image' % name)
            self.assertTrue(any('not armed' in text for text in self.blind_warnings[name]),
                            '%s did not warn about the missing camera: %s'
                            % (name, self.blind_warnings[name]))

    def test_the_right_detector_fired(self):
        deadline = time.time() + WALL_TIMEOUT
        while len(self.reasons) < len(self.monitors) and time.time() < deadline:
            time.sleep(0.01)
        for name, (_topic, expected) in self.monitors.items():
            self.assertIn(name, self.reasons, '%s published no ~loss reason' % name)
            detector = self.reasons[name].split(':')[0]
            allowed = CAN_FIRE[self.mode] if expected == 'any' else {expected}
            self.assertIn(detector, allowed, '%s: %s' % (name, self.reasons[name]))


def cases():
    """One TestCase per ~scenarios entry (DetectionDark, DetectionLost, ...)."""
    loader = unittest.TestLoader()
    return unittest.TestSuite(
        loader.loadTestsFromTestCase(type('Detection' + mode.capitalize(), (DetectionTest,), {'mode': mode}))
        for mode in sorted(rospy.get_param('~scenarios')))


if __name__ == '__main__':
    rospy.init_node('test_detection')
    rostest.rosrun('blind_navigation', 'detection', __name__ + '.cases')

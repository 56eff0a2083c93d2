"""The vision monitor: core/vision.py's debounced detectors on the camera, RTAB-Map's visual
odometry and ``odom_info_lite``; ``vision_lost``, ``~loss``, ``vision_back`` (docs/detection.md)."""
import threading

import rospy
from sensor_msgs.msg import CameraInfo, Image
from std_msgs.msg import Empty, String

from blind_navigation import names
from blind_navigation.core import mission_state
from blind_navigation.core.role_params import VISION_MONITOR
from blind_navigation.core.vision import (VisionBack, VisionLossMonitor, image_mean_intensity,
                                          odom_info_lost, wire_lost_reason)
from blind_navigation.ros import diagnostics
from blind_navigation.ros.clock import LoopClock
from blind_navigation.ros.common import subscribe, unsubscribe
from blind_navigation.ros.mission import Role
from blind_navigation.ros.odometry import ros_time
from blind_navigation.ros.faults import Expected

#: RTAB-Map's OdomInfo (rtabmap_msgs from 0.21 on; any MD5 sum: the lost flag's place stays)
ODOM_INFO = Expected(('rtabmap_msgs/OdomInfo', 'rtabmap_ros/OdomInfo'))
IMAGE_BUFFER = 1 << 24  # a whole camera frame per read: no backlog of stale images
#: s: the least wait between two stall checks; between the checks while vision is lost
MIN_CHECK_WAIT, BACK_CHECK = 0.01, 0.1


class VisionMonitor(Role):
    """Debounced vision-loss detection."""

    ROLE = 'vision_monitor'
    SCHEMA = VISION_MONITOR

    def __init__(self, layer):
        Role.__init__(self, layer)
        p, guard = self.params, self.guard
        self.enabled = enabled = set(p.detectors)
        self.lock = threading.Lock()
        self.done, self.warned = False, set()
        self.generation = 0   # the missions watched (new_mission watches anew)
        self.lost = self.back = None    # the loss detected (core/vision.Loss) and its VisionBack
        self.started = None   # first stall check: sim time may not have arrived yet here
        self.last_camera = self.last_vo = None
        self.lost_pub = rospy.Publisher(names.VISION_LOST, Empty, queue_size=1, latch=True)
        self.loss_pub = rospy.Publisher('~loss', String, queue_size=1, latch=True)
        self.back_pub = rospy.Publisher(names.VISION_BACK, String, queue_size=1)
        # kept across missions: a new subscription would get a latched vision_lost again
        self.manual_sub = subscribe(names.VISION_LOST, Empty, guard(self.on_vision_lost))
        self.camera_info_sub = None   # read until visual odometry arrives
        self.start_watching()
        VisionBack(self.monitor, p.vision_back_time)    # a bad vision_back_time fails now
        self.follow('vision monitor')
        self.log.info('watching with detectors %s', ', '.join(sorted(enabled)))

    def start_watching(self):
        """Fresh detectors, their inputs subscribed, the stall checks running."""
        p, enabled, guard = self.params, self.enabled, self.guard
        self.monitor = VisionLossMonitor(enabled, p.image_timeout, p.vo_timeout, p.debounce,
                                         p.dark_threshold, p.dark_frames, p.host_stall_gap)
        self.subscribers = []
        if 'dark' in enabled:
            self.camera_topic = names.CAMERA
            self.subscribers.append(subscribe(names.CAMERA, Image, guard(self.on_image), queue_size=1,
                                              buff_size=IMAGE_BUFFER))
        elif 'stall' in enabled:
            self.camera_topic = names.CAMERA_INFO
            self.camera_info_sub = subscribe(names.CAMERA_INFO, CameraInfo,
                                             guard(self.on_camera_info), queue_size=1)
        else:
            self.camera_topic = None
        self.camera_info_until_vo = self.camera_info_sub is not None and 'vo_stall' in enabled
        self.watching_vo = bool(enabled & {'vo_lost', 'vo_stall'})
        # the wheel odometry's arrivals tell a host stall from a vision fault
        self.feeds = [(self.layer.odometry, guard(self.on_wheel_odometry))] + (
            [(self.layer.visual_odometry, guard(self.on_vo))] if self.watching_vo else [])
        for feed, listener in self.feeds:
            feed.add_listener(listener, raw=True)
            feed.acquire(self.ROLE)
        if 'odom_info' in enabled:
            self.subscribers.append(subscribe(names.VO_ODOM_INFO, rospy.AnyMsg,
                                              guard(self.on_odom_info), expected=ODOM_INFO,
                                              queue_size=5))
        threading.Thread(target=guard(self.watch_stalls), args=(self.generation,),
                         name='vision_monitor_stalls', daemon=True).start()

    def on_camera_info(self, _msg):
        self.last_camera = rospy.get_time()
        self.feed(self.monitor.image, None)

    def on_image(self, msg):
        self.last_camera = rospy.get_time()
        try:
            mean = image_mean_intensity(msg.encoding, msg.height, msg.width, msg.step, msg.data,
                                        bool(msg.is_bigendian))
        except ValueError as error:
            mean = None
            self.warn_once('image', '%s on %s: dark detector idle'
                           % (error, rospy.resolve_name(names.CAMERA)))
        self.feed(self.monitor.image, mean)

    def on_wheel_odometry(self, _wire):
        self.monitor.host_flow(ros_time())

    def on_vo(self, wire):
        self.last_vo = rospy.get_time()
        self.feed(self.monitor.vo_odometry, wire_lost_reason(wire))
        if not self.camera_info_until_vo:
            return
        # its stall detector covers a camera stall from now on: camera_info unread
        with self.lock:
            subscriber, self.camera_info_sub = self.camera_info_sub, None
            self.camera_info_until_vo = False
            if subscriber is None:
                return
            # the camera-stall detector is fed no more: it must not take the silence for a stall
            self.monitor.enabled = self.monitor.enabled - {'stall'}
            self.camera_topic = None
        unsubscribe(subscriber)
        self.log.info('visual odometry arrives on %s: its stall detector watches for a camera '
                      'stall from now on; %s no longer read', rospy.resolve_name(names.VO_ODOM),
                      rospy.resolve_name(names.CAMERA_INFO))

    def on_odom_info(self, msg):
        if not ODOM_INFO.accepts(names.VO_ODOM_INFO, msg._connection_header):
            return      # refused
        try:
            lost = odom_info_lost(msg._buff)
        except ValueError as error:
            self.log.warn_throttle(10.0, '%s', error)
            return
        self.feed(self.monitor.odom_info_flag, lost)

    def on_vision_lost(self, msg):
        caller = msg._connection_header.get('callerid', '?')
        if caller != rospy.get_name():
            self.feed(self.monitor.manual, caller)

    def _new_mission(self):
        with self.lock:
            self.done, self.started, self.lost, self.back = False, None, None, None
            self.generation += 1
        self.log.info('new mission: watching again')
        self.start_watching()

    def _on_state(self, _old, new):
        if new in mission_state.TERMINAL:
            with self.lock:
                if self.done:
                    return
                self.done = True
                camera_info, self.camera_info_sub = self.camera_info_sub, None
            self.log.info('mission %s: no longer watching', new)
            for subscriber in self.subscribers + ([camera_info] if camera_info else []):
                unsubscribe(subscriber)
            for feed, listener in self.feeds:
                feed.remove_listener(listener)
                feed.release(self.ROLE)

    def watch_stalls(self, generation):
        """Check the stall detectors whenever one could fire next, while this mission is watched."""
        clock = LoopClock('vision stall checks', self.log,
                          then='watching on (the detectors start again from the new time)')
        while not rospy.is_shutdown() and not self.done and self.generation == generation:
            now = rospy.get_time()
            if now > 0.0:                 # zero: sim time has not started
                self.started = now if self.started is None else self.started
                waited = now - self.started
                if waited >= self.params.no_input_warning and self.camera_topic and self.last_camera is None:
                    self.warn_once('no_camera', 'nothing on %s after %.1f s: the camera detectors are '
                                   'not armed' % (rospy.resolve_name(self.camera_topic), waited))
                if waited >= self.params.no_input_warning and self.watching_vo and self.last_vo is None:
                    self.warn_once('no_vo', 'no visual odometry on %s after %.1f s: the visual-odometry '
                                   'detectors are not armed; detection falls back to the camera '
                                   'detectors' % (rospy.resolve_name(names.VO_ODOM), waited))
                self.feed(self.monitor.check)
            try:
                clock.sleep(max(self.next_check(now) - now, MIN_CHECK_WAIT))
            except rospy.ROSInterruptException:
                return

    def next_check(self, now):
        """ROS time of the next stall check (or of the no-input warning)."""
        if self.lost is not None:
            return now + BACK_CHECK       # the streams' messages drive the checks meanwhile
        checks = []
        for stall in (self.monitor.stall, self.monitor.vo_stall):
            if stall.name in self.monitor.enabled:
                checks.append(stall.due(now, self.monitor.host))
        if self.started is None:
            checks.append(now)
        elif now < self.started + self.params.no_input_warning:
            checks.append(self.started + self.params.no_input_warning)
        return min(checks) if checks else now + self.params.no_input_warning

    def feed(self, method, *args):
        """Run one core feed method now; act on a loss and on its end."""
        with self.lock:
            if self.done:
                return
            now = rospy.get_time()
            losses = method(now, *args)
            lost = self.lost
            if lost is None and losses:
                self.lost = lost = losses[0]
                # vision back only after a loss seen here, not after one declared by hand
                self.back = None if lost.detector == 'manual' else VisionBack(
                    self.monitor, self.params.vision_back_time)
            else:
                if lost is not None and self.back is not None and self.back.update(now):
                    self.lost = self.back = None
                    self.back_pub.publish(String(data='vision back after %.1f s (%s lost)' % (
                        now - self.params.vision_back_time - lost.since, lost.detector)))
                    self.log.warn('VISION BACK after %.1f s: watching for the next loss', now - lost.since)
                return
        self.log.warn('VISION LOST, detector %s: %s (%.2f s after the failure began)',
                      lost.detector, lost.reason, lost.t - lost.since)
        if lost.detector != 'manual':
            self.lost_pub.publish(Empty())
        self.loss_pub.publish(String(data='%s: %s' % (lost.detector, lost.reason)))
        self.layer.diagnostics.now()

    def warn_once(self, key, text):
        if key not in self.warned:
            self.warned.add(key)
            self.log.warn('%s', text)

    def _diagnose(self, stat):
        now = rospy.get_time()
        camera = '-' if self.last_camera is None else '%.2f' % (now - self.last_camera)
        if self.camera_topic is None and self.last_vo is not None:
            camera = 'not read (the visual-odometry stall detector covers it)'
        stat.add('camera age (s)', camera)
        stat.add('visual odometry age (s)', '-' if self.last_vo is None else '%.2f' % (now - self.last_vo))
        if self.done:
            stat.summary(diagnostics.OK, 'not watching (the mission has ended)')
        elif self.lost is not None:
            stat.summary(diagnostics.WARN, 'vision lost (%s)%s' % (self.lost.detector, '' if self.back
                         else '; declared by hand: not watching for its end'))
        elif self.warned & {'no_camera', 'no_vo'}:
            stat.summary(diagnostics.WARN, 'watching without %s' % ' and '.join(
                sorted({'no_camera': 'a camera', 'no_vo': 'visual odometry'}[key]
                       for key in self.warned & {'no_camera', 'no_vo'})))
        else:
            stat.summary(diagnostics.OK, 'watching')

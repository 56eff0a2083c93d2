"""vision_monitor: notices vision loss by itself and publishes /blind_navigation/vision_lost.

Watches the camera stream (stall, dark images), RTAB-Map's visual odometry
(lost convention, stall) and optionally RTAB-Map's odom_info ``lost`` flag, all
through the debounced detectors of core/vision.py, and publishes one
std_msgs/Empty on ``vision_lost_topic`` for the first loss of the mission; the
reason goes to the log and to the latched ``~loss`` (std_msgs/String). After
that it stops watching (one loss per mission). A vision_lost published by
anybody else (the manual trigger) is logged and also ends the watch.
"""
import threading

import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image
from std_msgs.msg import Empty, String

from blind_navigation.core.vision import VisionLossMonitor, image_mean_intensity, odom_info_lost
from blind_navigation.ros.common import load_params, odometry_lost_reason

IMAGE_BUFFER = 1 << 24  # a whole camera frame per read: no backlog of stale images


class VisionMonitorNode(object):
    """Debounced vision-loss detection over ROS topics.

    Params (DEFAULTS): camera_topic, vo_odom_topic, odom_info_topic,
    vision_lost_topic; detect_stall, detect_dark, detect_vo_lost,
    detect_vo_stall, detect_odom_info, detect_manual (per-detector enables);
    image_timeout, vo_timeout, debounce (s); dark_threshold (mean intensity
    0..255); dark_frames (consecutive dark images); check_rate (Hz, stall
    checks); no_image_warning (s without any image before a warning).
    """

    DEFAULTS = {
        'camera_topic': '/camera/rgb/image_rect_color',
        'vo_odom_topic': '/rtabmap/odom',
        'odom_info_topic': '/rtabmap/odom_info',
        'vision_lost_topic': '/blind_navigation/vision_lost',
        'detect_stall': True,
        'detect_dark': True,
        'detect_vo_lost': True,
        'detect_vo_stall': True,
        'detect_odom_info': True,
        'detect_manual': True,
        'image_timeout': 1.0,
        'vo_timeout': 1.0,
        'debounce': 0.5,
        'dark_threshold': 10.0,
        'dark_frames': 3,
        'check_rate': 20.0,
        'no_image_warning': 5.0,
    }

    def __init__(self):
        p = self.params = load_params(self.DEFAULTS)
        enabled = {name for name in ('stall', 'dark', 'vo_lost', 'vo_stall', 'odom_info', 'manual')
                   if getattr(p, 'detect_' + name)}
        self.monitor = VisionLossMonitor(enabled, p.image_timeout, p.vo_timeout, p.debounce,
                                         p.dark_threshold, p.dark_frames)
        self.lock = threading.Lock()
        self.done = False
        self.warned = set()
        self.started = None  # first timer tick: sim time may not have arrived yet here
        # Latched, as `rostopic pub -1` is: a node whose subscription connects late (the
        # subscription watchdog heals a missed registration) still gets the one loss.
        self.lost_pub = rospy.Publisher(p.vision_lost_topic, Empty, queue_size=1, latch=True)
        self.loss_pub = rospy.Publisher('~loss', String, queue_size=1, latch=True)
        self.subscribers = [rospy.Subscriber(p.vision_lost_topic, Empty, self.on_vision_lost)]
        if enabled & {'stall', 'dark'}:
            self.subscribers.append(rospy.Subscriber(p.camera_topic, Image, self.on_image,
                                                     queue_size=1, buff_size=IMAGE_BUFFER))
        if enabled & {'vo_lost', 'vo_stall'}:
            self.subscribers.append(rospy.Subscriber(p.vo_odom_topic, Odometry, self.on_vo,
                                                     queue_size=5))
        if 'odom_info' in enabled:
            self.subscribers.append(rospy.Subscriber(p.odom_info_topic, rospy.AnyMsg,
                                                     self.on_odom_info, queue_size=5))
        self.timer = rospy.Timer(rospy.Duration(1.0 / p.check_rate), self.on_timer)
        rospy.loginfo('vision_monitor: watching with detectors %s', ', '.join(sorted(enabled)))

    # --- inputs ---------------------------------------------------------------------------------
    def on_image(self, msg):
        mean = None
        if 'dark' in self.monitor.enabled:
            try:
                mean = image_mean_intensity(msg.encoding, msg.height, msg.width, msg.step,
                                            msg.data, bool(msg.is_bigendian))
            except ValueError as error:
                self.warn_once('image', '%s on %s: dark detector idle'
                               % (error, self.params.camera_topic))
        self.feed(self.monitor.image, mean)

    def on_vo(self, msg):
        self.feed(self.monitor.vo_odometry, odometry_lost_reason(msg))

    def on_odom_info(self, msg):
        msg_type = msg._connection_header.get('type', '')
        if not msg_type.endswith('/OdomInfo'):
            self.warn_once('odom_info_type', '%s carries %s, not rtabmap OdomInfo: ignored'
                           % (self.params.odom_info_topic, msg_type))
            return
        try:
            lost = odom_info_lost(msg._buff)
        except ValueError as error:
            rospy.logwarn_throttle(10.0, 'vision_monitor: %s' % error)
            return
        self.feed(self.monitor.odom_info_flag, lost)

    def on_vision_lost(self, msg):
        caller = msg._connection_header.get('callerid', '?')
        if caller != rospy.get_name():
            self.feed(self.monitor.manual, caller)

    def on_timer(self, _event):
        now = rospy.Time.now().to_sec()
        self.started = now if self.started is None else self.started
        if not self.monitor.stall.armed and self.monitor.enabled & {'stall', 'dark'}:
            waited = now - self.started
            if waited >= self.params.no_image_warning:
                self.warn_once('no_image', 'no image on %s after %.1f s: stall and dark detectors '
                               'are not armed until the first image' % (self.params.camera_topic, waited))
        self.feed(self.monitor.check)

    # --- output ---------------------------------------------------------------------------------
    def feed(self, method, *args):
        """Run one core feed method at the current ROS time; act on the first loss."""
        with self.lock:
            if self.done:
                return
            losses = method(rospy.Time.now().to_sec(), *args)
            if losses:
                self.fire(losses[0])

    def fire(self, loss):
        self.done = True
        rospy.logwarn('vision_monitor: VISION LOST, detector %s: %s (%.2f s after the failure '
                      'began); no longer watching', loss.detector, loss.reason, loss.t - loss.since)
        if loss.detector != 'manual':
            self.lost_pub.publish(Empty())
        self.loss_pub.publish(String(data='%s: %s' % (loss.detector, loss.reason)))
        self.timer.shutdown()
        for subscriber in self.subscribers:
            subscriber.unregister()

    def warn_once(self, key, text):
        if key not in self.warned:
            self.warned.add(key)
            rospy.logwarn('vision_monitor: %s', text)

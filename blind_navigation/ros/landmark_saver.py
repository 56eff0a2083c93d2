"""landmark_saver: the paper's subscriber (topic variant of the recorder).

On each blind_navigation/PathSample on /blind_navigation/sample whose command
is ``sample`` or ``final``, takes the latest odometry and saves one path
landmark (blind_navigation/recording.py: the same saving code as the service
variant's record_server). Publishes /blind_navigation/storage and
/blind_navigation/recorded_path.
"""
import rospy

from blind_navigation import names
from blind_navigation.msg import PathSample
from blind_navigation.ros.landmark_saving import LandmarkSaving


class LandmarkSaver(object):
    """Subscriber that saves a landmark per sample.

    Params: those of :class:`blind_navigation.ros.landmark_saving.LandmarkSaving`
    (odom_topic, landmark_file, fsync, odom_timeout).
    """

    def __init__(self):
        self.saving = LandmarkSaving('topic')
        self.sample_sub = rospy.Subscriber(names.SAMPLE, PathSample, self.on_sample, queue_size=20)

    def on_sample(self, msg):
        self.saving.save(msg.command, msg.yaw, msg.period, msg.header.stamp.to_sec())

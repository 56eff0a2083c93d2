"""The landmark saver: the paper's subscriber (topic variant of the recorder).

On each blind_navigation/PathSample on ``blind_navigation/sample`` whose
command is ``sample`` or ``final``, saves one path landmark from the odometry
at the tick (ros/landmark_saving.py: the same saving code as the service
variant's record server). Params: those of
:class:`~blind_navigation.ros.landmark_saving.LandmarkSaving`.
"""
from blind_navigation import names
from blind_navigation.msg import PathSample
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.landmark_saving import LandmarkSaving


class LandmarkSaver(object):
    """Subscriber that saves a landmark per sample."""

    ROLE = 'landmark_saver'

    def __init__(self, layer):
        self.saving = LandmarkSaving(layer, self.ROLE, 'topic')
        self.sample_sub = subscribe(names.SAMPLE, PathSample, self.on_sample, queue_size=20)

    def on_sample(self, msg):
        self.saving.save(msg.command, msg.yaw, msg.period, msg.header.stamp.to_sec())

"""The landmark saver: the paper's subscriber (topic variant of the recorder).

Each ``sample``/``final`` PathSample on ``blind_navigation/sample`` becomes one landmark
(ros/landmark_saving.py). It subscribes once its odometry has a state; restarted within
the mission it first catches up on the samples it missed.
"""
from blind_navigation import names
from blind_navigation.core.landmark_format import SampleMark
from blind_navigation.msg import PathSample
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.landmark_saving import LandmarkSaving


class LandmarkSaver(object):
    """Subscriber that saves a landmark per sample."""

    ROLE = 'landmark_saver'

    def __init__(self, layer):
        self.saving = LandmarkSaving(layer, self.ROLE, 'topic')
        self.sample_sub = None
        self.saving.when_ready(self._take_samples)

    def _take_samples(self):
        if self.saving.resuming:
            self.saving.start_catch_up(
                lambda: self.sample_sub is not None and self.sample_sub.get_num_connections() > 0)
        self.sample_sub = subscribe(names.SAMPLE, PathSample, self.saving.guard(self.on_sample),
                                    queue_size=20)

    def on_sample(self, msg):
        self.saving.save(msg.command, msg.yaw, msg.period, msg.header.stamp.to_sec(),
                         SampleMark(msg.recording, msg.seq) if msg.seq else None)

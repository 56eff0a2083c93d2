"""The landmark saver: the paper's subscriber (topic variant of the recorder).

On each blind_navigation/PathSample on ``blind_navigation/sample`` whose
command is ``sample`` or ``final``, saves one path landmark from the odometry
at the tick (ros/landmark_saving.py: the same saving code as the service
variant's record server). It subscribes once its odometry feed has a state:
it takes samples only when it can save them. Restarted within the mission, it
first catches up on the samples it missed (LandmarkSaving.start_catch_up),
once its subscription is connected; samples that arrive meanwhile wait. Params: those of
:class:`~blind_navigation.ros.landmark_saving.LandmarkSaving`.
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

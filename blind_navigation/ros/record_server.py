"""The record server: the paper's service server (service variant of the recorder,
3.3.3, Figure 4).

Serves ``blind_navigation/record_landmark`` once its odometry has a state; each request
saves one landmark with the topic variant's code (ros/landmark_saving.py) and answers
whether it was saved, its label, or why not.
"""
import rospy

from blind_navigation import names
from blind_navigation.ros.landmark_saving import LandmarkSaving
from blind_navigation.srv import RecordLandmark, RecordLandmarkResponse


class RecordServer(object):
    """Service server that saves a landmark per request."""

    ROLE = 'record_server'

    def __init__(self, layer):
        self.saving = LandmarkSaving(layer, self.ROLE, 'service')
        self.service = None
        self.saving.when_ready(self._serve)

    def _serve(self):
        self.service = rospy.Service(names.RECORD_LANDMARK, RecordLandmark,
                                     self.saving.guard(self.on_request))

    def on_request(self, request):
        label, why_not = self.saving.save(request.command, request.yaw, request.period,
                                          request.header.stamp.to_sec())
        return RecordLandmarkResponse(saved=bool(label), label=label, message=why_not)

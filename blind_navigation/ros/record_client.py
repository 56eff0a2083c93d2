"""The record client: the paper's service client (service variant of the recorder,
3.3.3, Figure 4): each sample on ``blind_navigation/sample`` becomes a request to
``blind_navigation/record_landmark``, once the server is up.
"""
import rospy

from blind_navigation import names
from blind_navigation.core.role_params import RECORD_CLIENT
from blind_navigation.msg import PathSample
from blind_navigation.ros.common import subscribe
from blind_navigation.srv import RecordLandmark


class RecordClient(object):
    """Forwards every PathSample to the record_landmark service."""

    ROLE = 'record_client'
    SCHEMA = RECORD_CLIENT

    def __init__(self, layer):
        self.params = layer.params(self.ROLE, self.SCHEMA)
        self.log = layer.logger(self.ROLE)
        self.guard = layer.guard(self.ROLE)
        self.calls = 0
        self.service = rospy.resolve_name(names.RECORD_LANDMARK)
        self.record = rospy.ServiceProxy(names.RECORD_LANDMARK, RecordLandmark, persistent=False)
        self.sample_sub = None

    def run(self):
        """Block until the server is up (or shutdown); then subscribe to the samples."""
        while not rospy.is_shutdown():
            try:
                rospy.wait_for_service(names.RECORD_LANDMARK, timeout=self.params.wait_log_period)
                break
            except rospy.ROSException:
                self.log.warn('still waiting for %s', self.service)
        else:
            return
        self.log.info('%s is up; forwarding %s', self.service, rospy.resolve_name(names.SAMPLE))
        self.sample_sub = subscribe(names.SAMPLE, PathSample, self.guard(self.on_sample),
                                    queue_size=20)

    def on_sample(self, msg):
        self.calls += 1
        try:
            response = self.record(header=msg.header, command=msg.command, yaw=msg.yaw,
                                   period=msg.period)
        except (rospy.ServiceException, rospy.ROSException) as error:
            self.log.error('%s call %d failed: %s', self.service, self.calls, error)
            return
        if not response.saved:
            self.log.warn('server did not save the %s sample: %s', msg.command, response.message)

"""The paper's public names under the mission owner (ros/mission_owner.py), one process.

``record_landmark`` (blind_navigation/RecordLandmark, with ``~recorder`` ``service``): a
request goes to the mission under the owner's lock (core/landmark_request.hand_in); the
mission's recording takes it at its next steps and answers, or it is withdrawn after
:data:`ANSWER_WAIT`. ``back_travel`` (blind_navigation/BackTravel): served so that clients
find it; every goal is rejected (:data:`REJECTED`). docs/recording.md, docs/DESIGN.md.
"""
import threading

import rospy

from blind_navigation import names
from blind_navigation.core.landmark_request import LandmarkRequest, hand_in, withdraw
from blind_navigation.msg import BackTravelAction, BackTravelResult
from blind_navigation.ros.clock import action_server
from blind_navigation.srv import RecordLandmark, RecordLandmarkResponse

#: s (wall) a request waits for the mission's answer: the recording takes it once odometry
#: covers its stamp and, with event sampling, 0.5 s later (core/motion_events' latency).
ANSWER_WAIT = 2.0
#: Why every BackTravel goal is rejected here.
REJECTED = ("the one-process layer drives its return itself (one mission object); landmark goals "
            "are served by paper.launch's back_travel_server (one_process:=false)")


class PaperNames(object):
    """``record_landmark`` (when ``owner.recorder`` is ``service``) and the ``back_travel``
    action of ``owner`` (a ros/mission_owner.MissionOwner: its lock, mission, log, guard)."""

    def __init__(self, owner):
        self.owner, self.log = owner, owner.log
        self.service = None
        if owner.recorder == 'service':
            self.service = rospy.Service(names.RECORD_LANDMARK, RecordLandmark,
                                         owner.guard(self._on_request))
            self.log.info('serving %s: a request is one more landmark of the mission\'s recording',
                          rospy.resolve_name(names.RECORD_LANDMARK))
        # no periodic status: actionlib publishes it (latched) at start and at each rejection
        self.action = action_server(names.BACK_TRAVEL, BackTravelAction, owner.guard, self._on_goal)

    def _on_request(self, request):
        """Hand the request in, wait for its answer: saved, label, or why not."""
        done = threading.Event()
        asked = LandmarkRequest(request.command, request.yaw, request.period,
                                request.header.stamp.to_sec(), lambda _: done.set())
        with self.owner.lock:
            hand_in(self.owner.mission, asked)
        if not done.wait(ANSWER_WAIT):
            with self.owner.lock:
                withdraw(self.owner.mission, asked, ANSWER_WAIT)
        label, why_not = asked.answer
        if label:
            self.log.info('requested landmark %s saved (psi %.3f rad, T %.3f s)', label,
                          request.yaw, request.period)
        else:
            self.log.warn_throttle(1.0, '%s: request %r not saved: %s',
                                   rospy.resolve_name(names.RECORD_LANDMARK), request.command, why_not)
        return RecordLandmarkResponse(saved=bool(label), label=label, message=why_not)

    def _on_goal(self, handle):
        """Reject the goal naming why (logged once per goal); actionlib publishes the result
        and the status that ends it ``REJECTED`` with :data:`REJECTED` as its text."""
        self.log.warn('%s goal %s rejected: %s', rospy.resolve_name(names.BACK_TRAVEL),
                      handle.get_goal_id().id, REJECTED)
        handle.set_rejected(BackTravelResult(), REJECTED)

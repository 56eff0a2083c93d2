"""The return's route on the wire: the client's call of
``blind_navigation/set_return_route`` (blind_navigation/SetReturnRoute) with the
route (core/route.Route), the landmarks of its goals (return order) and how many
are done, and the server's reading of the request back into a Route.
"""
import json

import rospy

from blind_navigation import names
from blind_navigation.core.route import Route
from blind_navigation.srv import SetReturnRoute


def set_return_route(route, landmarks, completed, frame_id, timeout):
    """Set the route on the back-travel server; None if it took it, else why not."""
    service = rospy.resolve_name(names.SET_RETURN_ROUTE)
    try:
        rospy.wait_for_service(names.SET_RETURN_ROUTE, timeout)
        call = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
        response = call(header=rospy.Header(stamp=rospy.Time.now(), frame_id=frame_id),
                        route=json.dumps(route.to_lists()),
                        landmarks=[value for lm in landmarks for value in lm.as_list()],
                        completed=completed)
    except (rospy.ROSException, rospy.ServiceException) as error:
        return 'cannot set the return route on %s: %s' % (service, error)
    return None if response.ok else 'return route refused: %s' % response.message


def route_of(request):
    """The core/route.Route a SetReturnRoute request carries; ValueError if none."""
    try:
        return Route.from_lists(json.loads(request.route))
    except (TypeError, ValueError) as error:   # json's errors are ValueErrors
        raise ValueError('route: %s' % error)

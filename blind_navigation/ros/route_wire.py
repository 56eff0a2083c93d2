"""The return's route on the wire (blind_navigation/ReturnRoute, typed): the
client's call of ``blind_navigation/set_return_route`` (blind_navigation/SetReturnRoute)
with the route (core/route.Route), the landmarks of its goals (return order)
and how many are done, and the server's reading of the request back into a
Route (:func:`route_of`: a route of another version or a bad field is refused).
"""
import rospy

from blind_navigation import names
from blind_navigation.core.route import SECTION_FIELDS, Route, route_lists
from blind_navigation.msg import ReturnRoute, RouteSection
from blind_navigation.srv import SetReturnRoute


def route_message(route):
    """The ReturnRoute message of a core/route.Route."""
    return ReturnRoute(version=ReturnRoute.ROUTE_VERSION, x=route.x, y=route.y, speed=route.speed,
                       corner=route.corner,
                       sections=[RouteSection(*[getattr(s, f) for f in SECTION_FIELDS])
                                 for s in route.sections])


def route_of(request):
    """The core/route.Route a SetReturnRoute request carries; ValueError naming the
    bad field (the same checks as core/route.Route.from_lists)."""
    msg = request.route
    if msg.version != ReturnRoute.ROUTE_VERSION:
        raise ValueError('route: version %d, this server reads version %d'
                         % (msg.version, ReturnRoute.ROUTE_VERSION))
    try:
        return Route.from_lists(route_lists(msg))
    except ValueError as error:
        raise ValueError('route: %s' % error)


def set_return_route(route, landmarks, completed, frame_id, timeout):
    """Set the route on the back-travel server: (why not or None, the server's home
    tolerance, m; 0: its mode does not check the position, docs/safety.md "home")."""
    service = rospy.resolve_name(names.SET_RETURN_ROUTE)
    try:
        rospy.wait_for_service(names.SET_RETURN_ROUTE, timeout)
        call = rospy.ServiceProxy(names.SET_RETURN_ROUTE, SetReturnRoute)
        response = call(header=rospy.Header(stamp=rospy.Time.now(), frame_id=frame_id),
                        route=route_message(route),
                        landmarks=[value for lm in landmarks for value in lm.as_list()],
                        completed=completed)
    except (rospy.ROSException, rospy.ServiceException) as error:
        return 'cannot set the return route on %s: %s' % (service, error), 0.0
    return (None if response.ok else 'return route refused: %s' % response.message,
            response.home_tolerance)

"""The return's route on the wire (blind_navigation/ReturnRoute, typed): the message of a
core/route.Route the owner sends with ``set_return_route`` (ros/paper_adapter.py), and the
server's reading of the request back into a Route (:func:`route_of`: a route of another
version or a bad field is refused).
"""
from blind_navigation.core.route import SECTION_FIELDS, Route, route_lists
from blind_navigation.msg import ReturnRoute, RouteSection


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


"""The fake TurtleBot's world: a rectangular arena (walls or cliff edges) and round obstacles.

Turns the true pose into Kobuki bumper, cliff and wheel-drop states; walls and obstacles
block motion (the wheels slip on), a wheel over a cliff edge drops. World files (YAML)::

    arena: {x_min: -1.0, x_max: 20.0, y_min: -0.85, y_max: 0.85, edge: wall}
    obstacles: [{x: 2.0, y: 0.5, radius: 0.15}]
"""
import math
from collections import namedtuple

from ..core.geometry import Pose2D, wrap_angle

ROBOT_RADIUS = 0.177          # m, Kobuki body (354 mm diameter)
CONTACT_MARGIN = 0.005        # m, a bumper reads pressed this close to a surface
CLIFF_SENSORS = {'left': math.radians(45.0), 'center': 0.0, 'right': -math.radians(45.0)}
CLIFF_SENSOR_RADIUS = 0.15    # m from the centre
WHEELS = {'left': 0.115, 'right': -0.115}   # lateral offsets, m
BUMPER_CENTER_HALF_WIDTH = math.radians(30.0)
EDGES = ('wall', 'cliff')

Contacts = namedtuple('Contacts', 'bumper cliff wheel_drop')
Contacts.__doc__ = 'Sets of Kobuki sensor names currently pressed / over a cliff / dropped.'


def _bumper_for(angle):
    """Kobuki bumper hit by a contact at ``angle`` (rad, robot frame), or None behind the robot."""
    if abs(angle) <= BUMPER_CENTER_HALF_WIDTH:
        return 'center'
    if abs(angle) <= math.pi / 2.0:
        return 'left' if angle > 0 else 'right'
    return None


class Arena(object):
    """``bounds`` (x_min, x_max, y_min, y_max) or None for no edge; ``obstacles`` [(x, y, radius)]."""

    def __init__(self, bounds=None, edge='wall', obstacles=()):
        if edge not in EDGES:
            raise ValueError('arena edge must be one of %s, got %r' % (EDGES, edge))
        if bounds is not None and not (bounds[0] < bounds[1] and bounds[2] < bounds[3]):
            raise ValueError('arena bounds need x_min < x_max and y_min < y_max, got %r' % (bounds,))
        self.bounds = tuple(bounds) if bounds is not None else None
        self.edge = edge
        self.obstacles = [tuple(o) for o in obstacles]

    def _surfaces(self, pose):
        """(distance from the robot centre, direction in world frame) to each blocking surface."""
        x, y = pose.x, pose.y
        if self.bounds is not None and self.edge == 'wall':
            x_min, x_max, y_min, y_max = self.bounds
            yield x - x_min, math.pi
            yield x_max - x, 0.0
            yield y - y_min, -math.pi / 2.0
            yield y_max - y, math.pi / 2.0
        for ox, oy, radius in self.obstacles:
            yield math.hypot(ox - x, oy - y) - radius, math.atan2(oy - y, ox - x)

    def penetration(self, pose):
        """How deep (m) the robot body overlaps walls/obstacles; <= 0 when free."""
        return max([ROBOT_RADIUS - gap for gap, _ in self._surfaces(pose)] or [-math.inf])

    def _outside(self, x, y):
        x_min, x_max, y_min, y_max = self.bounds
        return not (x_min <= x <= x_max and y_min <= y <= y_max)

    def _points_outside(self, pose, offsets):
        """Names of robot-frame points (name -> (forward, left)) outside the arena."""
        if self.bounds is None or self.edge != 'cliff':
            return frozenset()
        c, s = math.cos(pose.yaw), math.sin(pose.yaw)
        return frozenset(name for name, (fx, fy) in offsets.items()
                         if self._outside(pose.x + c * fx - s * fy, pose.y + s * fx + c * fy))

    def contacts(self, pose):
        """Contacts at ``pose``."""
        bumper = set()
        for gap, direction in self._surfaces(pose):
            if gap <= ROBOT_RADIUS + CONTACT_MARGIN:
                name = _bumper_for(wrap_angle(direction - pose.yaw))
                if name:
                    bumper.add(name)
        cliff_points = {n: (CLIFF_SENSOR_RADIUS * math.cos(a), CLIFF_SENSOR_RADIUS * math.sin(a))
                        for n, a in CLIFF_SENSORS.items()}
        wheel_points = {n: (0.0, lateral) for n, lateral in WHEELS.items()}
        return Contacts(frozenset(bumper), self._points_outside(pose, cliff_points),
                        self._points_outside(pose, wheel_points))

    def resolve(self, old, new):
        """The pose the robot really reaches moving from ``old`` toward ``new``, and its contacts.

        A move that pushes the body deeper into a wall or obstacle keeps the old
        position (the wheels slip); turning on the spot is always possible.
        """
        if self.penetration(new) > max(self.penetration(old), 0.0) + 1e-12:
            new = Pose2D(old.x, old.y, new.yaw)
        return new, self.contacts(new)


def arena_from_dict(data, where='world'):
    """Arena from a world/mission mapping (keys ``arena`` and ``obstacles``, both optional)."""
    data = data or {}
    spec = data.get('arena')
    bounds, edge = None, 'wall'
    if spec is not None:
        try:
            bounds = tuple(float(spec[k]) for k in ('x_min', 'x_max', 'y_min', 'y_max'))
        except (KeyError, TypeError, ValueError) as error:
            raise ValueError('%s: arena needs numeric x_min, x_max, y_min, y_max (%s)' % (where, error))
        edge = spec.get('edge', 'wall')
    obstacles = []
    for i, item in enumerate(data.get('obstacles') or []):
        try:
            obstacles.append((float(item['x']), float(item['y']), float(item['radius'])))
        except (KeyError, TypeError, ValueError) as error:
            raise ValueError('%s: obstacles[%d] needs numeric x, y, radius (%s)' % (where, i, error))
    try:
        return Arena(bounds, edge, obstacles)
    except ValueError as error:
        raise ValueError('%s: %s' % (where, error))

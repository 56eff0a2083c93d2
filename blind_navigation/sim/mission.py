"""Scripted operator missions: what a human teleoperating the robot would send, over time.

A mission file (``config/missions/<name>.yaml``; format: docs/fake_turtlebot.md) holds
``segments`` or ``waypoints``, a ``rate``, optional ``operator`` settings and a world.
``command_at(t)`` is the open-loop script; ``make_operator()`` gives the person who
drives it watching the robot (sim/operator.Operator), for the mission driver node and
the harness alike.
"""
import math
import os

import yaml

from ..core.geometry import wrap_angle
from .operator import Operator, operator_params
from .config_dir import config_dir

MISSION_DIR = config_dir('missions')
DEFAULT_RATE = 10.0


class Mission(object):
    """Segments ``[(v, w, duration)]`` played back to back; ``rate`` Hz; ``world`` dict; ``name``."""

    def __init__(self, segments, rate=DEFAULT_RATE, world=None, name='mission', description='',
                 operator=None):
        if not segments:
            raise ValueError('%s: a mission needs at least one segment' % name)
        if not (rate > 0):
            raise ValueError('%s: rate must be > 0 Hz, got %r' % (name, rate))
        self.segments = [tuple(float(x) for x in s) for s in segments]
        self.rate = float(rate)
        self.world = world or {}
        self.name = name
        self.description = description
        self.duration = sum(s[2] for s in self.segments)
        #: operator parameters (sim/operator.py) or None for the open-loop script
        self.operator = None if operator is None else operator_params(operator, name)

    def make_operator(self):
        """A fresh sim/operator.Operator for this mission, or None (open-loop script)."""
        return None if self.operator is None else Operator(self, self.operator)

    def command_at(self, t):
        """(v, w) the operator sends ``t`` s after the mission start; None once it is over."""
        if t < 0:
            raise ValueError('%s: command_at(t=%r) before the mission start' % (self.name, t))
        elapsed = 0.0
        for v, w, duration in self.segments:
            elapsed += duration
            if t < elapsed:
                return v, w
        return None

    def nominal_length(self):
        """Path length (m) the commands would give on an ideal robot."""
        return sum(abs(v) * duration for v, _, duration in self.segments)


def _segment(item, where):
    if not isinstance(item, dict):
        raise ValueError('%s: a segment is a mapping, got %r' % (where, item))
    unknown = set(item) - {'v', 'w', 'distance', 'angle', 'duration'}
    if unknown:
        raise ValueError('%s: unknown key(s) %s' % (where, sorted(unknown)))
    v, w = float(item.get('v', 0.0)), float(item.get('w', 0.0))
    given = [k for k in ('distance', 'angle', 'duration') if k in item]
    if len(given) != 1:
        raise ValueError('%s: give exactly one of distance, angle, duration (got %s)' % (where, given))
    amount = float(item[given[0]])
    speed = {'distance': abs(v), 'angle': abs(w), 'duration': 1.0}[given[0]]
    if amount < 0 or speed == 0:
        raise ValueError('%s: %s=%r cannot be covered at v=%r, w=%r' % (where, given[0], amount, v, w))
    return v, w, amount / speed


def _waypoint_segments(spec, where):
    try:
        v, w, points = float(spec['v']), abs(float(spec['w'])), spec['points']
    except (KeyError, TypeError, ValueError) as error:
        raise ValueError('%s: waypoints need v, w and points (%s)' % (where, error))
    if v <= 0 or w <= 0:
        raise ValueError('%s: waypoint speeds must be > 0, got v=%r w=%r' % (where, v, w))
    x = y = yaw = 0.0
    segments = []
    for i, point in enumerate(points):
        px, py = float(point[0]), float(point[1])
        heading = math.atan2(py - y, px - x)
        turn = wrap_angle(heading - yaw)
        if abs(turn) > 1e-9:
            segments.append((0.0, math.copysign(w, turn), abs(turn) / w))
        segments.append((v, 0.0, math.hypot(px - x, py - y) / v))
        x, y, yaw = px, py, heading
    return segments


def mission_from_dict(data, name='mission'):
    """Mission from a parsed mission file; ValueError naming the file and the bad entry."""
    if not isinstance(data, dict):
        raise ValueError('%s: a mission file is a mapping' % name)
    if ('segments' in data) == ('waypoints' in data):
        raise ValueError('%s: give either segments or waypoints' % name)
    if 'segments' in data:
        segments = [_segment(item, '%s: segments[%d]' % (name, i)) for i, item in enumerate(data['segments'])]
    else:
        segments = _waypoint_segments(data['waypoints'], '%s: waypoints' % name)
    world = {k: data[k] for k in ('arena', 'obstacles') if k in data}
    operator = data.get('operator', False)
    if operator is True:
        operator = {}
    elif operator is False:
        operator = None
    return Mission(segments, data.get('rate', DEFAULT_RATE), world, name, data.get('description', ''),
                   operator)


def load_mission(name_or_path):
    """Mission from a name in config/missions/ or a YAML path."""
    path = name_or_path
    if os.path.sep not in name_or_path and not name_or_path.endswith('.yaml'):
        path = os.path.join(MISSION_DIR, name_or_path + '.yaml')
    if not os.path.isfile(path):
        known = sorted(f[:-5] for f in os.listdir(MISSION_DIR)) if os.path.isdir(MISSION_DIR) else []
        raise ValueError('mission %r not found (%s); known: %s' % (name_or_path, path, known))
    with open(path) as stream:
        return mission_from_dict(yaml.safe_load(stream), path)

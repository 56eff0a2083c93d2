"""Missions given as command series: an operator's ``(v, w)`` over time, played open loop.

:class:`CommandSeries` is a mission whose :meth:`~CommandSeries.command_at` bisects
(O(log n) per tick); :func:`load_trajectory` reads a real robot's trajectory converted to
commands (``config/paths/<name>.csv``: ``t, v, w`` rows, ``#`` header lines with source
and licence; config/paths/README.md lists them).
"""
import bisect
import csv
import os
import statistics

from ..core.landmark import KOBUKI_MAX_V, KOBUKI_MAX_W
from .mission import Mission
from .config_dir import config_dir

PATHS_DIR = config_dir('paths')
#: Tolerance on mission times, s (operator ticks are k * control_dt, summed in floats).
TIME_EPSILON = 1e-9


class CommandSeries(Mission):
    """A mission of pieces ``[(v, w, duration)]`` played back to back (see module docstring)."""

    def __init__(self, segments, rate=10.0, name='series', description=''):
        super(CommandSeries, self).__init__(segments, rate, None, name, description)
        for index, (v, w, duration) in enumerate(self.segments):
            if not duration > 0:
                raise ValueError('%s: piece %d lasts %r s (must be > 0)' % (name, index, duration))
            if abs(v) > KOBUKI_MAX_V + 1e-9 or abs(w) > KOBUKI_MAX_W + 1e-9:
                raise ValueError('%s: piece %d (v %r, w %r) beyond the Kobuki limits' % (name, index, v, w))
        self._ends = []
        elapsed = 0.0
        for _, _, duration in self.segments:
            elapsed += duration
            self._ends.append(elapsed)

    def command_at(self, t):
        """(v, w) the operator sends ``t`` s after the mission start; None once it is over."""
        if t < 0:
            raise ValueError('%s: command_at(t=%r) before the mission start' % (self.name, t))
        index = bisect.bisect_right(self._ends, t + TIME_EPSILON)
        if index >= len(self.segments):
            return None
        v, w, _ = self.segments[index]
        return v, w


def trajectory_names():
    """Names of the trajectories shipped in config/paths (without .csv)."""
    return sorted(f[:-4] for f in os.listdir(PATHS_DIR) if f.endswith('.csv'))


def load_trajectory(name_or_path, rate=10.0):
    """A :class:`CommandSeries` from a ``t, v, w`` CSV: a name in config/paths or a
    path. ValueError naming the file and line for a malformed one."""
    path = name_or_path
    if os.path.sep not in name_or_path and not name_or_path.endswith('.csv'):
        path = os.path.join(PATHS_DIR, name_or_path + '.csv')
    if not os.path.isfile(path):
        raise ValueError('trajectory %r not found (%s); known: %s'
                         % (name_or_path, path, ', '.join(trajectory_names())))
    header, rows = [], []
    with open(path) as stream:
        lines = [(number, line) for number, line in enumerate(stream, 1)]
    body = []
    for number, line in lines:
        if line.startswith('#'):
            header.append(line[1:].strip())
        elif line.strip():
            body.append((number, line))
    if not body or [c.strip() for c in body[0][1].split(',')] != ['t', 'v', 'w']:
        raise ValueError('%s: the first data line must be the column names t,v,w' % path)
    for number, fields in zip((n for n, _ in body[1:]), csv.reader(line for _, line in body[1:])):
        try:
            t, v, w = (float(x) for x in fields)
        except ValueError:
            raise ValueError('%s:%d: expected three numbers t,v,w, got %r' % (path, number, fields))
        if rows and not t > rows[-1][0]:
            raise ValueError('%s:%d: t = %r does not increase' % (path, number, t))
        rows.append((t, v, w))
    if len(rows) < 2:
        raise ValueError('%s: needs at least two rows' % path)
    spacing = statistics.median(b[0] - a[0] for a, b in zip(rows, rows[1:]))
    segments = [(v, w, t_next - t) for (t, v, w), (t_next, _, _) in zip(rows, rows[1:])]
    segments.append((rows[-1][1], rows[-1][2], spacing))
    name = os.path.splitext(os.path.basename(path))[0]
    return CommandSeries(segments, rate, name, '\n'.join(header))

"""The mission owner's diagnostics' parts (diagnostic_msgs, ros/mission_owner.py): the
``mission`` summary (``aborted`` an error; ``recovered`` or a degraded mission a warning),
``odometry`` (its age; an error while the robot turns or returns) and ``landmark file``
(the recorder's file and its size).
"""
import os

from blind_navigation.core import mission_state as state
from blind_navigation.ros import diagnostics


def mission_summary(stat, current, reason, warnings=''):
    """The mission status's level and line: ``aborted`` an ERROR, ``recovered`` (stopped away
    from home: someone takes the robot) or a degraded mission a WARN."""
    if current == state.ABORTED:
        stat.summary(diagnostics.ERROR, 'aborted: %s' % reason)
    elif current == state.RECOVERED:
        stat.summary(diagnostics.WARN, 'recovered: %s' % reason)
    elif warnings:
        stat.summary(diagnostics.WARN, '%s: %s' % (current, warnings))
    else:
        stat.summary(diagnostics.OK, '%s%s' % (current or '', ': ' + reason if reason else ''))


def odometry_status(stat, odometry, current, timeout):
    """The ``odometry`` feed's age (stale beyond ``timeout`` s: an error while the mission,
    ``current``, turns or returns, else a warning) and its refused messages."""
    level = diagnostics.ERROR if current in (state.ROTATING, state.RETURNING) else diagnostics.WARN
    diagnostics.age_status(stat, 'odometry', odometry.age(), timeout, level, level,
                           listening=odometry.listening())
    stat.add('refused messages', odometry.refused)


def file_status(stat, landmark_file, current):
    """The configured ``landmark_file``, the mission's file and its size (unreadable: an
    error while the mission, ``current``, records, turns or returns)."""
    stat.add('file', landmark_file)
    try:
        real = os.path.realpath(landmark_file)
        stat.add('mission file', real)
        stat.add('bytes', os.path.getsize(real))
        stat.summary(diagnostics.OK, os.path.basename(real))
    except OSError as error:
        level = diagnostics.ERROR if current in (state.RECORDING, state.ROTATING,
                                                 state.RETURNING) else diagnostics.OK
        stat.summary(level, 'no landmark file yet' if level == diagnostics.OK else
                     'landmark file unreadable: %s' % error.strerror)

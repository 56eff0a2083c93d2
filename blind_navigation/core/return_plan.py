"""What a return drives, decided before the first goal (no ROS): whether the
recorded file allows a way back (:func:`recording_problem`), the warning for
its gaps (:func:`gaps_warning`), the route (:func:`plan_route`: core/route,
pruned by core/pruning with ``prune_loops``) and the goals in return order
(:func:`return_goals`). The back-travel client's return runner
(ros/return_runner.py) sends the goals; docs/back_travel.md tells the why.
:func:`nothing_to_retrace`: a return asked for before the robot moved.
"""
import math

from .odometry_reset import is_untrusted_reset
from .pruning import prune_route
from .route import build_route


def recording_problem(loaded, reported_lost=None, loss_error=''):
    """Why the recording (core/store.LoadedLandmarks) gives no way back, or None:
    landmarks lost at its end (``reported_lost``: the recorder's count, None when
    it reported none or the return resumes) or an odometry reset it could not carry."""
    lost_tail = loaded.lost_after_end(reported_lost) if reported_lost is not None else 0
    if lost_tail:
        return ('the last %d landmark(s) of the recording could not be written (%s): '
                'the way back from here is unknown; not travelling back' % (lost_tail, loss_error))
    resets = [gap for gap in loaded.gaps if is_untrusted_reset(gap.reason)]
    if resets:
        return ('the recording crossed an odometry reset it could not carry across '
                '(%s, before %s): the way back across it is unknown; not travelling '
                'back' % (resets[-1].reason, resets[-1].before))
    return None


def gaps_warning(loaded):
    """The mission's warning for a recording with gaps, or ''."""
    if not loaded.gaps:
        return ''
    return 'the recording has %d gap(s) (%d landmark(s) lost): the return bridges them' % (
        len(loaded.gaps), loaded.missing)


def return_goals(labels, landmarks):
    """[(label, landmark)] in return order (the last recorded first)."""
    return list(zip(labels, landmarks))[::-1]


def plan_route(landmarks, anchor, params, prune, correction=None):
    """(route, log lines): the route from ``anchor`` over ``landmarks`` (recording
    order), with ``prune`` pruned in the frame of ``correction`` (a GyroCorrection
    or None). ValueError if it cannot be built."""
    route = build_route(landmarks, anchor, params)
    if not prune:
        return route, []
    result = prune_route(route, landmarks, correction, params)
    return result.route, result.describe()


def nothing_to_retrace(recorded, start, here, tolerance):
    """Why a return would have nothing to retrace, or None: the recording holds at most
    ``tolerance`` m of path (``recorded``) and the robot's odometry ``here`` [x, y] is
    within ``tolerance`` of where the recording began (``start``); the mission is then
    home without a turn (docs/safety.md, "home"). ``start`` or ``here`` None: unknown."""
    if start is None or here is None or recorded > tolerance:
        return None
    off = math.hypot(here[0] - start[0], here[1] - start[1])
    if off > tolerance:
        return None
    return ('nothing to retrace: %.3f m recorded, the robot %.3f m from where the mission began '
            '(within %.2f m); no turn' % (recorded, off, tolerance))

"""What a return drives, decided before the first goal: :func:`recording_problem` (is there a
way back), the warnings, :func:`plan_return` (the route, pruned) and :func:`nothing_to_retrace`."""
import math
from collections import namedtuple

from . import outcome
from .odometry_reset import is_untrusted_reset
from .pruning import prune_route
from .route import build_route

#: m, rad: the most a loss of landmarks the return bridges (docs/safety.md, "Decide before the turn").
STILL_LOSS_DISTANCE = 0.005
STILL_LOSS_TURN = 0.1

WriteLoss = namedtuple('WriteLoss', 'count distance turn error')
NO_LOSS = WriteLoss(0, 0.0, 0.0, '')


def write_loss(writer, error=''):
    """The WriteLoss (what could not be written) of a core/mission_files.LandmarkWriter."""
    return WriteLoss(writer.lost, writer.lost_distance, writer.lost_turn, error)


def still_loss(loss):
    """True if the landmarks of ``loss`` (a WriteLoss) were all taken standing still."""
    return loss.distance <= STILL_LOSS_DISTANCE and loss.turn <= STILL_LOSS_TURN


def recording_problem(loaded, loss=None):
    """Why ``loaded`` (a core/store.LoadedPath) gives no way back (a core/outcome.Ending), or
    None: ``loss`` (a WriteLoss) not all standing still, or an untrusted odometry reset."""
    if loss is not None and loss.count and not still_loss(loss):
        tail = loaded.lost_after_end(loss.count)
        what, where = (('the last %d landmark(s) of the recording' % tail, 'from here') if tail else
                       ('%d landmark(s) within the recording' % loss.count, 'across them'))
        return outcome.Ending(outcome.STORAGE, (
            '%s could not be written (%s): %.3f m and %.2f rad of the path are in no file (a '
            'standstill is at most %.3f m and %.2f rad): the way back %s is unknown; not '
            'travelling back' % (what, loss.error, loss.distance, loss.turn,
                                 STILL_LOSS_DISTANCE, STILL_LOSS_TURN, where)))
    resets = [gap for gap in loaded.gaps if is_untrusted_reset(gap.reason)]
    if resets:
        return outcome.Ending(outcome.ODOMETRY, (
            'the recording crossed an odometry reset it could not carry across (%s, before %s): '
            'the way back across it is unknown; not travelling back' % (resets[-1].reason,
                                                                        resets[-1].before)))
    return None


def frame_lost(lost):
    """Why a mission whose odometry frame was ``lost`` cannot go back."""
    return '%s: the way back is unknown; not travelling back' % lost


def damage_warning(loss, path):
    """The mission's warning while landmarks (``loss``) could not be written to ``path``."""
    return ('RECORDING DAMAGED: %d landmark(s) (%.3f m, %.2f rad of the path) could not be '
            'written to %s: %s' % (loss.count, loss.distance, loss.turn, path, loss.error))


def return_warning(loaded, loss=None):
    """The mission's warning (or '') for a return over ``loaded``'s gaps after ``loss`` (or None)."""
    parts = []
    if loaded.gaps:
        parts.append('the recording has %d gap(s) (%d landmark(s) lost): the return bridges them'
                     % (len(loaded.gaps), loaded.missing))
    if loss is not None and loss.count:
        parts.append('%d landmark(s) could not be written (%s) while the robot stood still '
                     '(%.3f m, %.2f rad): the return bridges them' % (loss.count, loss.error,
                                                                      loss.distance, loss.turn))
    return '; '.join(parts)


def plan_return(landmarks, anchor, params, prune, correction=None):
    """(route, core/pruning.PruneResult or None) from ``anchor`` over ``landmarks``, pruned
    with ``prune`` in the frame of ``correction``; ValueError if it cannot be built."""
    route = build_route(landmarks, anchor, params)
    if not prune:
        return route, None
    result = prune_route(route, landmarks, correction, params)
    return result.route, result


def nothing_to_retrace(recorded, start, here, tolerance):
    """Why a return has nothing to retrace (``recorded``, ``here`` to ``start`` <= ``tolerance``)."""
    if start is None or here is None or recorded > tolerance:
        return None
    off = math.hypot(here[0] - start[0], here[1] - start[1])
    if off > tolerance:
        return None
    return ('nothing to retrace: %.3f m recorded, the robot %.3f m from where the mission began '
            '(within %.2f m); no turn' % (recorded, off, tolerance))

"""Whether a restarted layer may resume the return its progress file
(core/progress.py) records: :func:`resume_from_file` (or, on a record read
already, :func:`resume_decision`) answers :data:`RESUME`, :data:`IGNORE`
(nothing was under way) or :data:`ABORT` (a return was under way and cannot
safely continue, or the file cannot be trusted: docs/safety.md, "Faults");
:func:`settle_abort` then records the abort, so the next start is clean;
:func:`kept_return` is what a resumed return continues from.
"""
import datetime
import enum
import math
import os
from collections import namedtuple

from . import mission_state as state
from .heading_correction import CorrectedOdometry, correct_landmarks
from .plausibility import Limits
from .progress import (PROGRESS_DEFAULTS, ProgressError, ReturnProgress, as_point, file_digest,
                       kept_heading, kept_route, load_progress, plain_correction, save_progress)
from .return_plan import recording_problem
from .store import LandmarkFileError, load_landmarks


class Action(enum.Enum):
    """What a restarted layer does with a return's progress."""
    RESUME = 'resume'
    IGNORE = 'ignore'
    ABORT = 'abort'


RESUME, IGNORE, ABORT = Action.RESUME, Action.IGNORE, Action.ABORT
ResumeDecision = namedtuple('ResumeDecision', 'action reason progress')
ResumeDecision.__doc__ = ('What a restarted layer does: ``action`` (RESUME, IGNORE or ABORT), '
                          '``reason`` (one line naming the file and, for a bad file, the field), '
                          '``progress`` (the ReturnProgress read, None if none could be).')


def resume_decision(progress, now, digest, position, mission=None,
                    resume_timeout=PROGRESS_DEFAULTS['resume_timeout'],
                    resume_max_offset=PROGRESS_DEFAULTS['resume_max_offset'], landmark_count=None):
    """May a restarted layer resume the return ``progress`` (a ReturnProgress)? A
    :class:`ResumeDecision`.

    ``now``: wall time, s; ``digest``: sha256 of ``landmark_file`` now (None
    if it cannot be read); ``position``: the robot's odometry [x, y] now
    (None if unknown: wait for odometry before asking); ``mission``: the
    current mission's id, if known; ``landmark_count``: how many landmarks
    the file holds now, if the caller loaded it. Rules, in order:

    - finished (home, aborted): IGNORE;
    - unfinished, and both this record and the caller name a mission, and
      they differ: IGNORE (left over from an earlier mission);
    - otherwise a return of this mission was under way: ABORT if it was
      updated more than ``resume_timeout`` s ago or in the future (the clock
      changed), during the pi turn (the heading is unknown), if the file is
      gone or changed or does not hold ``landmarks`` landmarks, if the
      robot's position is unknown or more than
      ``resume_max_offset`` m from where the return stopped; else RESUME.
    """
    action, why = resume_check(progress, now, digest, resume_timeout, mission)
    if action == RESUME and landmark_count is not None and landmark_count != progress.landmarks:
        action, why = ABORT, ('%s: landmarks: the return was over %d landmarks, the file holds '
                              '%d' % (progress.landmark_file, progress.landmarks, landmark_count))
    if action == RESUME:
        problem = position_check(progress, position, resume_max_offset)
        if problem:
            action, why = ABORT, 'cannot resume the return of %s: %s' % (progress.landmark_file,
                                                                         problem)
    return ResumeDecision(action, why, progress)


def resume_check(progress, now, digest, resume_timeout, mission=None):
    """The file part of :func:`resume_decision` (not where the robot is):
    ``(action, reason)``."""
    if not progress.unfinished:
        return IGNORE, 'the last return (%s) ended %s' % (progress.landmark_file, progress.status)
    if mission is not None and progress.mission is not None and mission != progress.mission:
        return IGNORE, ('an unfinished return of %s is left over from mission %s (this is mission '
                        '%s); not resuming it' % (progress.landmark_file, progress.mission, mission))
    age = now - float(progress.updated)
    if age < 0:
        return ABORT, ('the unfinished return of %s was updated %.0f s in the future (the clock '
                       'changed?): cannot tell how old it is' % (progress.landmark_file, -age))
    if age > resume_timeout:
        return ABORT, ('the unfinished return of %s was last updated %.0f s ago (resume_timeout '
                       '%.0f s): too old to resume' % (progress.landmark_file, age, resume_timeout))
    if progress.status == state.ROTATING:
        return ABORT, 'restarted during the pi turn: the heading is unknown, not travelling back'
    if digest is None:
        return ABORT, 'landmark file %s of the unfinished return is gone' % progress.landmark_file
    if digest != progress.digest:
        return ABORT, 'landmark file %s changed since the return started' % progress.landmark_file
    if progress.anchor is None or progress.position is None:
        return ABORT, 'the unfinished return has no anchor/position to resume from'
    return RESUME, 'resuming the return of %s after %d of %d landmarks' % (
        progress.landmark_file, progress.completed, progress.landmarks)


def position_check(progress, position, resume_max_offset):
    """None if the robot (odometry ``position`` [x, y], None if unknown) is within
    ``resume_max_offset`` m of where ``progress`` stopped, else why not."""
    if position is None:
        return 'no odometry to check where the robot is'
    try:
        x, y = as_point(position)
    except (TypeError, ValueError) as error:
        return 'the robot\'s position is unusable: %s' % error
    offset = math.hypot(x - progress.position[0], y - progress.position[1])
    if offset > resume_max_offset:
        return ('the robot is %.2f m from where the return stopped (resume_max_offset %.2f m): '
                'odometry reset or robot moved' % (offset, resume_max_offset))
    return None


def resume_from_file(path, now, position, mission=None,
                     resume_timeout=PROGRESS_DEFAULTS['resume_timeout'],
                     resume_max_offset=PROGRESS_DEFAULTS['resume_max_offset'], limits=Limits()):
    """What a restarted layer does with the progress at ``path``: a
    :class:`ResumeDecision` (see :func:`resume_decision`). No file:
    IGNORE; a file that cannot be trusted: ABORT naming the file and field.
    The landmark file's digest and count are taken here (loaded with
    ``limits``; a file that no longer loads: ABORT naming it)."""
    try:
        progress = load_progress(path)
    except ProgressError as error:
        return ResumeDecision(ABORT, 'cannot trust the return progress: %s' % error, None)
    if progress is None:
        return ResumeDecision(IGNORE, 'no return progress at %s' % path, None)
    digest = count = None
    if progress.unfinished and progress.status != state.ROTATING:
        try:
            digest = file_digest(progress.landmark_file)
            count = len(load_landmarks(progress.landmark_file, limits).landmarks)
        except OSError:
            digest = None
        except LandmarkFileError as error:
            return ResumeDecision(ABORT, 'landmark file unusable: %s' % error, progress)
    return resume_decision(progress, now, digest, position, mission, resume_timeout,
                           resume_max_offset, count)


def settle_abort(path, decision, now):
    """Record an ABORT ``decision`` at ``path`` so the next start does not decide
    again: the progress read is marked aborted with the reason; an untrusted
    file is first renamed to ``<path>.bad-<time>`` (kept for inspection) and
    replaced by an aborted record. Returns the name it was set aside as, or
    None. StorageError (naming the file) if it cannot be written."""
    if decision.action != ABORT:
        raise ValueError('only an abort is settled, not %r' % (decision.action,))
    if decision.progress is not None:
        save_progress(path, decision.progress.finish(state.ABORTED, decision.reason, now))
        return None
    aside = None
    if os.path.lexists(path):
        stamp = datetime.datetime.fromtimestamp(now).strftime('%Y%m%d-%H%M%S')
        aside, n = '%s.bad-%s' % (path, stamp), 1
        while os.path.lexists(aside):
            aside, n = '%s.bad-%s-%d' % (path, stamp, n), n + 1
        os.rename(path, aside)
    save_progress(path, ReturnProgress.aborted(decision.reason, now))
    return aside


KeptReturn = namedtuple('KeptReturn', 'loaded landmarks route correction reference frame done '
                        'travelled anchor')
KeptReturn.__doc__ = ('What a resumed return continues from: the landmark file ``loaded``, its '
                      '``landmarks`` in the corrected frame, the ``route``, the heading ``correction``, '
                      'its ``reference`` and ``frame`` (core/heading_correction.CorrectedOdometry, '
                      'None without one), the goals ``done``, m ``travelled``, the ``anchor``.')


def resumed_route(progress, digest, goals, path):
    """(route, problem): the route ``progress`` (kept at ``path``) keeps, if the landmark file
    (sha256 ``digest``, ``goals`` landmarks) is still the one its return started over."""
    if digest != progress.digest or goals != progress.landmarks:
        return None, 'landmark file %s changed since the return started' % progress.landmark_file
    try:
        return kept_route(progress), None
    except ValueError as error:
        return None, 'cannot resume: the route in %s: %s' % (path, error)


def kept_return(progress, path, limits=Limits()):
    """(:class:`KeptReturn`, None) of a RESUME decision's ``progress`` (kept at ``path``; the
    landmark file loaded with ``limits``), or (None, why it cannot be resumed)."""
    try:
        loaded = load_landmarks(progress.landmark_file, limits=limits)
        digest = file_digest(progress.landmark_file)
    except OSError as error:
        return None, 'landmark file unusable: %s: cannot read: %s' % (progress.landmark_file,
                                                                     error.strerror)
    except LandmarkFileError as error:
        return None, 'landmark file unusable: %s' % error
    route, problem = resumed_route(progress, digest, len(loaded.landmarks), path)
    problem = problem or getattr(recording_problem(loaded, None), 'reason', None)
    if problem:
        return None, problem
    correction = reference = frame = None
    landmarks = loaded.landmarks
    if kept_heading(progress) is not None:
        try:
            correction, reference, frame = plain_correction(kept_heading(progress))
            CorrectedOdometry.started(correction, reference, snapshot=frame)
        except ValueError as error:
            return None, 'cannot resume: %s' % error
        landmarks = correct_landmarks(landmarks, correction)
    return KeptReturn(loaded, landmarks, route, correction, reference, frame, progress.completed,
                      progress.travelled, tuple(progress.anchor)), None

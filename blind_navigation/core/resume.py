"""Whether a restarted layer may resume the return its progress file records
(:func:`resume_from_file`: RESUME, IGNORE or ABORT; docs/safety.md, "Faults"), recording an
abort (:func:`settle_abort`) and what a resumed return continues from (:func:`kept_return`)."""
import datetime
import math
import os
from collections import namedtuple

from . import mission_state as state
from .heading_correction import CorrectedOdometry, correct_landmarks
from .plausibility import Limits
from .progress import (PROGRESS_DEFAULTS, ProgressError, ReturnProgress, as_point, file_digest,
                       load_progress, plain_correction, save_progress)
from .return_plan import recording_problem
from .route import Route
from .store import LandmarkFileError, load_landmarks


RESUME, IGNORE, ABORT = 'resume', 'ignore', 'abort'
ResumeDecision = namedtuple('ResumeDecision', 'action reason progress')


def resume_decision(progress, now, digest, position, mission=None,
                    resume_timeout=PROGRESS_DEFAULTS['resume_timeout'],
                    resume_max_offset=PROGRESS_DEFAULTS['resume_max_offset'], landmark_count=None):
    """A ResumeDecision for ``progress``: finished or another mission's, IGNORE; too old,
    mid-turn, the file (sha256 ``digest``, None: gone; ``landmark_count``) changed or the
    robot (``position``) away, ABORT; else RESUME."""
    return ResumeDecision(*_verdict(progress, now, digest, position, mission, resume_timeout,
                                    resume_max_offset, landmark_count), progress)


def _verdict(progress, now, digest, position, mission, resume_timeout, resume_max_offset, count):
    """``(action, reason)`` of :func:`resume_decision`."""
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
    if count is not None and count != progress.landmarks:
        return ABORT, ('%s: landmarks: the return was over %d landmarks, the file holds %d'
                       % (progress.landmark_file, progress.landmarks, count))
    cannot = 'cannot resume the return of %s: ' % progress.landmark_file
    if position is None:
        return ABORT, cannot + 'no odometry to check where the robot is'
    try:
        x, y = as_point(position)
    except (TypeError, ValueError) as error:
        return ABORT, cannot + 'the robot\'s position is unusable: %s' % error
    offset = math.hypot(x - progress.position[0], y - progress.position[1])
    if offset > resume_max_offset:
        return ABORT, cannot + ('the robot is %.2f m from where the return stopped '
                                '(resume_max_offset %.2f m): odometry reset or robot moved'
                                % (offset, resume_max_offset))
    return RESUME, 'resuming the return of %s after %d of %d landmarks' % (
        progress.landmark_file, progress.completed, progress.landmarks)


def resume_from_file(path, now, position, mission=None,
                     resume_timeout=PROGRESS_DEFAULTS['resume_timeout'],
                     resume_max_offset=PROGRESS_DEFAULTS['resume_max_offset'], limits=Limits()):
    """:func:`resume_decision` for the progress at ``path`` (none: IGNORE; untrusted: ABORT)."""
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
    """Record an ABORT ``decision`` at ``path``; returns where an untrusted file was set aside."""
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
    save_progress(path, ReturnProgress(
        landmark_file='', digest='', landmarks=0, anchor=None, frame_id='', completed=0,
        position=None, status=state.ABORTED, updated=float(now), reason=str(decision.reason)))
    return aside


KeptReturn = namedtuple('KeptReturn', 'loaded landmarks route correction reference frame done '
                        'travelled anchor')


def kept_return(progress, path, limits=Limits()):
    """(KeptReturn, None) of a RESUME decision's ``progress``, or (None, why not)."""
    try:
        loaded = load_landmarks(progress.landmark_file, limits=limits)
        digest = file_digest(progress.landmark_file)
    except OSError as error:
        return None, 'landmark file unusable: %s: cannot read: %s' % (progress.landmark_file,
                                                                     error.strerror)
    except LandmarkFileError as error:
        return None, 'landmark file unusable: %s' % error
    if digest != progress.digest or len(loaded.landmarks) != progress.landmarks:
        return None, 'landmark file %s changed since the return started' % progress.landmark_file
    try:
        if progress.route is None:
            raise ValueError('no route kept')
        route = Route.from_lists(progress.route['route'])
    except ValueError as error:
        return None, 'cannot resume: the route in %s: %s' % (path, error)
    problem = getattr(recording_problem(loaded, None), 'reason', None)
    if problem:
        return None, problem
    correction = reference = frame = None
    landmarks, heading = loaded.landmarks, progress.route['heading']
    if heading is not None:
        try:
            correction, reference, frame = plain_correction(heading)
            CorrectedOdometry.started(correction, reference, snapshot=frame)
        except ValueError as error:
            return None, 'cannot resume: %s' % error
        landmarks = correct_landmarks(landmarks, correction)
    return KeptReturn(loaded, landmarks, route, correction, reference, frame, progress.completed,
                      progress.travelled, tuple(progress.anchor)), None

"""The mission owner's return progress (core/progress.py) next to the landmark file: written
at each step, read at start-up to resume or abort; one that cannot be written is a warning."""
import os
import time

from . import mission_state as state, outcome
from .geometry import distance
from .landmark import Limits
from .progress import (ProgressError, ReturnProgress, file_digest, heading_record, progress_path,
                       save_progress)
from .resume import ABORT, IGNORE, kept_return, resume_from_file, settle_abort


class MissionProgress(object):
    """The progress of a core/mission.Mission's returns (``mission_id()``, ``frame_id()``)."""

    def __init__(self, landmark_file, mission_id, frame_id, log, changed=None):
        self.landmark_file, self.mission_id, self.frame_id = landmark_file, mission_id, frame_id
        self.path = progress_path(landmark_file)
        self.log, self.mission = log, None
        self.warning = ''           # why the progress cannot be written, or ''
        self._changed = changed     # called when ``warning`` changes
        self.forget()

    def save(self, progress):
        """Keep and persist ``progress``; if it cannot: ``warning``, the stale file removed."""
        self.progress = progress
        try:
            save_progress(self.path, progress)
            warning = ''
        except (OSError, ProgressError) as error:
            warning = ('the return progress cannot be written (%s): no resume after a crash%s'
                       % (error, self._remove_stale()))
        if warning != self.warning:
            self.warning = warning
            if warning:
                self.log.warn('%s', warning)
            if self._changed is not None:
                self._changed()

    def _remove_stale(self):
        """Remove the progress file an earlier step left; '' or what is left over."""
        try:
            os.unlink(self.path)
        except FileNotFoundError:
            pass
        except OSError as error:
            return ' (and the older %s cannot be removed: %s)' % (self.path, error.strerror)
        return ''

    def forget(self):
        """A new mission: the last return's progress forgotten."""
        self.progress, self.at, self.travelled, self.route = None, None, 0.0, None

    def _route_data(self):
        m = self.mission
        frame = m.corrector.snapshot() if m.corrector is not None else None
        return {'route': self.route.to_lists(), 'heading': heading_record(
            m.correction, m.reference, frame) if m.config.heading_correction else None}

    def first_state(self, mission, position, params):
        """The core/resume.KeptReturn of a return a previous run left, or None (``mission``
        aborted if one cannot continue); ``position()`` waits for the robot's [x, y]."""
        limits = Limits(params.max_v, params.max_w)
        if not os.path.lexists(self.path):
            return None
        decision = resume_from_file(self.path, time.time(), position(), self.mission_id(),
                                    params.resume_timeout, params.resume_max_offset, limits)
        if decision.action == IGNORE:
            self.log.info('%s', decision.reason)
            return None
        if decision.action == ABORT:
            try:
                settle_abort(self.path, decision, time.time())
            except (OSError, ProgressError) as error:
                self.log.error('cannot record the abort in %s: %s', self.path, error)
            mission.cancel(decision.reason, outcome.RESUME)
            return None
        self.progress = decision.progress
        self.log.warn('%s (%s)', decision.reason, self.path)
        kept, reason = kept_return(self.progress, self.path, limits)
        if kept is None:
            self.save(self.progress.finish(state.ABORTED, reason, time.time()))
            mission.cancel(reason, outcome.RESUME)
            return None
        self.route, self.travelled = kept.route, kept.travelled
        return kept

    def update(self, m, route):
        """After a step of ``m``: the turn began, the return began (``route``), a goal was done."""
        self.mission, progress = m, self.progress
        if progress is None and m.correction is not None:
            self.save(ReturnProgress.begin(self.landmark_file, m.anchor, self.frame_id(),
                                           time.time(), self.mission_id()))
        elif route is not None and self.route is None and progress is not None \
                and progress.status == state.ROTATING:
            self.route = route
            self._start(progress, len(m.drive.goals))
        elif m.state == state.RETURNING and m.last is not None:
            self._driven(m, progress)

    def _start(self, progress, goals):
        try:
            digest = file_digest(progress.landmark_file)
        except OSError as error:
            self.log.warn('no return progress: cannot read %s: %s', progress.landmark_file,
                          error.strerror)
            return
        self.save(progress.start(digest, goals, time.time(), route=self._route_data()))

    def _driven(self, m, progress):
        if self.at is not None:
            self.travelled += distance(self.at[0], self.at[1], m.last.x, m.last.y)
        self.at = [m.last.x, m.last.y]
        done = getattr(m.drive, 'index', 0)
        if progress is not None and progress.status == state.RETURNING and done > progress.completed:
            progress = progress.goal_done(min(done, progress.landmarks), time.time(), self.at,
                                          self.travelled)
            self.save(progress._replace(route=self._route_data()).checked())

    def ending(self, new, reason):
        """The mission becomes ``new``: a terminal state (or ``docking``: home) ends the progress."""
        progress, m = self.progress, self.mission
        if progress is None or not progress.unfinished or new not in state.TERMINAL + (state.DOCKING,):
            return
        position = [m.last.x, m.last.y] if m.last is not None else None
        new = state.HOME if new == state.DOCKING else new
        try:
            if new == state.HOME and progress.status == state.RETURNING:    # its last goal
                progress = progress.goal_done(progress.landmarks, time.time(), position)
            progress = progress.finish(new, reason, time.time(), position)
        except ProgressError as error:      # home, but the return's start was never kept
            self.log.warn('the return progress keeps its last step: %s', error)
            return
        self.save(progress)

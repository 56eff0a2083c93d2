"""The persisted return progress (core/progress.py), next to the landmark file: written
atomically at each step, read at start-up for the first state (resume, abort or idle) and a
restarted layer's route and heading correction (ProgressKeeper), for the mission owner
(MissionProgress). A progress that cannot be written is a warning (the
stale file removed), never a reason to stop.
"""
import os
import time
from types import SimpleNamespace

from . import mission_state as state, outcome
from .geometry import distance
from .landmark import Limits
from .progress import (ProgressError, ReturnProgress, file_digest, heading_record, progress_path,
                       route_record, save_progress)
from .resume import ABORT, IGNORE, kept_return, resume_from_file, settle_abort


class ProgressKeeper(object):
    """The progress of the returns recorded in ``landmark_file``; ``correction``: the
    layer's heading-correction receiver (None without the correction)."""

    def __init__(self, landmark_file, correction, log, changed=None):
        self.path = progress_path(landmark_file)
        self.correction = correction
        self.log = log
        self.progress = None
        self.warning = ''           # why the progress cannot be written, or ''
        self._changed = changed     # called when ``warning`` changes

    def save(self, progress):
        """Keep and persist ``progress`` (atomically, next to the landmark file). If it
        cannot be written the mission goes on: ``warning`` says so (WARN, once) and the
        stale file is removed, so a restart does not resume from an older step."""
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

    def first_state(self, position, mission_id, params, limits):
        """(state, reason): ``returning`` to resume an unfinished return of this
        mission, ``aborted`` if one was under way but cannot continue (or its
        progress cannot be trusted; the abort is recorded), else ``idle``
        (core/resume.resume_from_file). ``position()`` waits for the robot's [x, y]."""
        if not os.path.lexists(self.path):
            return state.IDLE, ''
        decision = resume_from_file(self.path, time.time(), position(), mission_id,
                                    params.resume_timeout, params.resume_max_offset, limits)
        if decision.action == IGNORE:
            self.log.info('%s', decision.reason)
            return state.IDLE, ''
        if decision.action == ABORT:
            try:
                settle_abort(self.path, decision, time.time())
            except (OSError, ProgressError) as error:
                self.log.error('cannot record the abort in %s: %s', self.path, error)
            return state.ABORTED, decision.reason
        self.progress = decision.progress
        self.log.warn('%s (%s)', decision.reason, self.path)
        return state.RETURNING, 'resume after a restart'

    def route_data(self, route):
        """The route record (core/progress.route_record) of ``route`` and, with the
        heading correction, the correction and the corrected frame's state now."""
        return route_record(route, self.correction.to_plain() if self.correction is not None
                            else None)


class MissionProgress(object):
    """The progress of a core/mission.Mission's returns (ros/mission_owner.py), kept by a
    :class:`ProgressKeeper` at each step; ``mission_id()`` and
    ``frame_id()`` name the mission and the odometry frame; a return a previous run left is
    resumed or aborted (:meth:`first_state`)."""

    def __init__(self, landmark_file, mission_id, frame_id, log, changed=None):
        self.landmark_file, self.mission_id, self.frame_id = landmark_file, mission_id, frame_id
        self.mission = None
        self.keeper = ProgressKeeper(landmark_file, SimpleNamespace(to_plain=self._heading), log,
                                     changed)
        self.forget()

    def forget(self):
        """A new mission: the last return's progress forgotten (its file replaced at the next)."""
        self.keeper.progress, self.at, self.travelled, self.route = None, None, 0.0, None

    def _heading(self):
        m = self.mission
        frame = m.corrector.snapshot() if m.corrector is not None else None
        return heading_record(m.correction, m.reference, frame) if m.config.heading_correction \
            else None

    def first_state(self, mission, position, params):
        """A return of this mission a previous run left: the core/resume.KeptReturn to resume
        it from, or None with ``mission`` aborted naming why it cannot continue
        (core/resume.py); None if there is none."""
        limits = Limits(params.max_v, params.max_w)
        first, reason = self.keeper.first_state(position, self.mission_id(), params, limits)
        kept = None
        if first == state.RETURNING:
            kept, reason = kept_return(self.keeper.progress, self.keeper.path, limits)
            if kept is None:
                self.keeper.save(self.keeper.progress.finish(state.ABORTED, reason, time.time()))
        if first != state.IDLE and kept is None:
            mission.cancel(reason, outcome.RESUME)
        if kept is not None:
            self.route, self.travelled = kept.route, kept.travelled
        return kept

    def update(self, m, route):
        """After a step of ``m``: the turn began (its correction), the return began
        (``route``, its goals), a goal was done."""
        self.mission, progress = m, self.keeper.progress
        if progress is None and m.correction is not None:
            self.keeper.save(ReturnProgress.begin(self.landmark_file, m.anchor, self.frame_id(),
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
            self.keeper.log.warn('no return progress: cannot read %s: %s', progress.landmark_file,
                                 error.strerror)
            return
        self.keeper.save(progress.start(digest, goals, time.time(),
                                        route=self.keeper.route_data(self.route)))

    def _driven(self, m, progress):
        if self.at is not None:
            self.travelled += distance(self.at[0], self.at[1], m.last.x, m.last.y)
        self.at = [m.last.x, m.last.y]
        done = getattr(m.drive, 'index', 0)
        if progress is not None and progress.status == state.RETURNING and done > progress.completed:
            progress = progress.goal_done(min(done, progress.landmarks), time.time(), self.at,
                                          self.travelled)
            self.keeper.save(progress._replace(route=self.keeper.route_data(self.route)).checked())

    def ending(self, new, reason):
        """The mission becomes ``new`` for ``reason``: a terminal state ends the return's progress
        (``docking``: the return ended home)."""
        progress, m = self.keeper.progress, self.mission
        if progress is None or not progress.unfinished or new not in state.TERMINAL + (state.DOCKING,):
            return
        position = [m.last.x, m.last.y] if m.last is not None else None
        new = state.HOME if new == state.DOCKING else new
        try:
            if new == state.HOME and progress.status == state.RETURNING:    # its last goal
                progress = progress.goal_done(progress.landmarks, time.time(), position)
            progress = progress.finish(new, reason, time.time(), position)
        except ProgressError as error:      # home, but the return's start was never kept
            self.keeper.log.warn('the return progress keeps its last step: %s', error)
            return
        self.keeper.save(progress)

"""The back-travel client's persisted return progress (core/progress.py), next to the
landmark file: written atomically at each step, read at start-up for the first state
(resume, abort or idle) and a restarted layer's route and heading correction. A progress
that cannot be written is a warning (the stale file removed), never a reason to stop.
"""
import os
import time

from blind_navigation.core import mission_state as state
from blind_navigation.core.progress import (ProgressError, kept_heading, progress_path,
                                            route_record, save_progress)
from blind_navigation.core.resume import ABORT, IGNORE, resume_from_file, settle_abort


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

    def restore_heading(self):
        """The heading correction kept in the progress, installed (the whole layer
        restarted mid-return); None, or why it cannot be."""
        kept = kept_heading(self.progress)
        if kept and self.correction is not None and not self.correction.received:
            try:
                self.correction.install_plain(kept)
            except ValueError as error:
                return 'cannot resume: %s' % error
        return None

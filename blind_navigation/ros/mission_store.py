"""The mission's landmark file as core/mission's store (the owner's and the paper's savers'):
appends, gaps, load, write loss; its StorageUsage and diagnostics."""
import os

import rospy

from blind_navigation.core.files import StorageError
from blind_navigation.core.recorder import SpaceWatch
from blind_navigation.core.return_plan import damage_warning, write_loss
from blind_navigation.core.store import load_landmarks
from blind_navigation.msg import StorageUsage
from blind_navigation.ros import diagnostics
from blind_navigation.ros.common import RoleLog


class FileStore(object):
    """The store of ``writer``'s file; ``error``: the last failed write; ``space``: its free space."""

    def __init__(self, writer):
        self.writer, self.error, self.log = writer, '', RoleLog(rospy.get_name())
        self.space = SpaceWatch(os.path.dirname(writer.path))

    def append(self, landmark, sample=None):
        """The label of ``landmark`` (``sample``: its SampleMark), None: lost (logged, ``error``)."""
        try:
            return self.writer.append(landmark, sample)
        except StorageError as error:
            self.error = str(error)
            self.log.error('LANDMARK LOST: %s', error)

    def note_gap(self, reason):
        """Note an odometry gap: the next landmark's d counts from the new odometry."""
        try:
            gap = self.writer.note_gap(reason)
            self.log.error('odometry discontinuity: %s noted in %s; the next landmark counts from '
                           'the new odometry', gap, self.writer.path)
        except StorageError as error:
            self.error = str(error)
            self.log.error('gap not noted: %s', error)

    def finish(self):
        """The file finished (a failure logged, kept in ``error`` unless one is)."""
        try:
            self.writer.finish()
        except StorageError as error:
            self.error = self.error or str(error)
            self.log.error('%s', error)

    def load(self):
        self.finish()
        return load_landmarks(self.writer.path)

    def loss(self):
        return write_loss(self.writer, self.error)

    def close(self):
        self.writer.close()

    def warning(self):
        """RECORDING DAMAGED while landmarks could not be written, else ''."""
        loss = self.loss()
        return damage_warning(loss, self.writer.path) if loss.count or self.error else ''

    def storage(self, now):
        """The StorageUsage at ``now`` (rospy.Time), the free space checked."""
        warning, appeared = self.space.update(now.to_sec(), self.writer.bytes, self.writer.count)
        if appeared:
            self.log.warn('%s', warning)
        writer, mark = self.writer, self.writer.sample
        metres = float(writer.total_distance)
        per_metre = writer.bytes / metres if metres > 0.0 else 0.0
        msg = StorageUsage(file=writer.path, landmarks=int(writer.count), bytes=int(writer.bytes),
                           distance=metres, bytes_per_metre=per_metre,
                           lost=writer.lost, lost_distance=writer.lost_distance,
                           lost_turn=writer.lost_turn, error=self.error, space_warning=warning,
                           recording=mark.recording if mark else 0.0, sample=mark.seq if mark else 0)
        msg.header.stamp = now
        return msg

    def status(self, stat, finished):
        """The recording's diagnostics; ``finished``: the recording is over."""
        writer = self.writer
        for name, value in (('file', writer.path), ('landmarks', writer.count),
                            ('bytes', writer.bytes), ('lost', writer.lost)):
            stat.add(name, value)
        if self.error:
            stat.summary(diagnostics.ERROR, '%d landmark(s) lost: %s' % (writer.lost, self.error))
        elif self.space.warning:
            stat.summary(diagnostics.WARN, self.space.warning)
        elif finished:
            stat.summary(diagnostics.OK, 'recording finished: %d landmarks' % writer.count)
        else:
            stat.summary(diagnostics.OK, 'recording: %d landmarks, %.2f m'
                         % (writer.count, writer.total_distance))

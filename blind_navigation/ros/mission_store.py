"""The mission's landmark file as core/mission's store, for the mission owner: appends,
gaps, the load at the loss and the write loss, a failed write logged and kept."""
import os

import rospy

from blind_navigation.core.files import StorageError
from blind_navigation.core.recorder import SpaceWatch
from blind_navigation.core.return_plan import damage_warning, write_loss
from blind_navigation.core.store import load_landmarks
from blind_navigation.ros.landmark_saving import landmark_lost, note_gap
from blind_navigation.ros.layer import RoleLog


class FileStore(object):
    """The mission's landmark file as core/mission's store (append, load, loss); a failed
    write is counted by the writer (lost) and kept in ``error``; ``space``: its free space."""

    def __init__(self, writer):
        self.writer, self.error, self.log = writer, '', RoleLog(rospy.get_name())
        self.space = SpaceWatch(os.path.dirname(writer.path))

    def append(self, landmark):
        try:
            return self.writer.append(landmark)
        except StorageError as error:
            self.error = str(error)
            landmark_lost(self.log, error)

    def note_gap(self, reason):
        try:
            note_gap(self.writer, reason, self.log)
        except StorageError as error:
            self.error = str(error)
            self.log.error('gap not noted: %s', error)

    def load(self):
        try:
            self.writer.finish()
        except StorageError as error:
            self.error = self.error or str(error)
        return load_landmarks(self.writer.path)

    def loss(self):
        return write_loss(self.writer, self.error)

    def close(self):
        self.writer.close()

    def warning(self):
        """RECORDING DAMAGED while landmarks could not be written, else ''."""
        loss = self.loss()
        return damage_warning(loss, self.writer.path) if loss.count or self.error else ''

"""The mission's landmark file as core/mission's store, for the mission owner: appends,
gaps, the load at the loss and the write loss, a failed write logged and kept."""
import os

import rospy

from blind_navigation.core.files import StorageError
from blind_navigation.core.recorder import SpaceWatch
from blind_navigation.core.return_plan import write_loss
from blind_navigation.core.store import load_landmarks


class FileStore(object):
    """The mission's landmark file as core/mission's store (append, load, loss); a failed
    write is counted by the writer (lost) and kept in ``error``; ``space``: its free space."""

    def __init__(self, writer):
        self.writer, self.error = writer, ''
        self.space = SpaceWatch(os.path.dirname(writer.path))

    def append(self, landmark):
        try:
            self.writer.append(landmark)
        except StorageError as error:
            self.error = str(error)
            rospy.logerr('%s: landmark lost: %s', rospy.get_name(), error)

    def note_gap(self, reason):
        try:
            gap = self.writer.note_gap(reason)
            rospy.logerr('%s: odometry discontinuity: %s noted in %s; the next landmark counts '
                         'from the new odometry', rospy.get_name(), gap, self.writer.path)
        except StorageError as error:
            self.error = str(error)
            rospy.logerr('%s: gap not noted: %s', rospy.get_name(), error)

    def load(self):
        try:
            self.writer.finish()
        except StorageError as error:
            self.error = self.error or str(error)
        return load_landmarks(self.writer.path)

    def loss(self):
        return write_loss(self.writer, self.error)

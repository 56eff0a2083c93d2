"""The mission state as every role of a process sees it (:class:`MissionStateView`) and
:class:`Role`, what every role of ros/layer has."""
import threading

import rospy
from std_msgs.msg import String

from .. import names
from ..core import mission_state
from .common import subscribe


class MissionStateView(object):
    """The mission state (None before any) of the owner node ``owner``."""

    def __init__(self, owner, guard):
        self.owner = rospy.resolve_name(owner)
        self.state = None
        self._delivery = threading.RLock()      # one change delivered at a time, in order
        self._callbacks = []
        self._subscriber = subscribe(names.STATE, String, guard(self._on_state), queue_size=10)

    def on_change(self, callback):
        """``callback(old, new)`` on every change, and at once ``(None, state)`` if it is known."""
        with self._delivery:
            self._callbacks.append(callback)
            if self.state is not None:
                callback(None, self.state)

    def on_new_mission(self, callback):
        """``callback()`` when ``new_mission`` starts the next mission (terminal -> ``idle``)."""
        self.on_change(lambda old, new: mission_state.starts_new_mission(old, new) and callback())

    def _on_state(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        if sender != self.owner and sender != rospy.get_name():
            rospy.logwarn_throttle(5.0, '%s: mission state %r from %s refused: only %s owns the '
                                   'mission state' % (rospy.get_name(), msg.data, sender, self.owner))
        elif msg.data not in mission_state.ALL:
            rospy.logwarn_throttle(5.0, '%s: unknown mission state %r from %s refused'
                                   % (rospy.get_name(), msg.data, sender))
        else:
            self.set_local(msg.data)

    def set_local(self, new):
        """The mission moved to ``new`` (the owner, hosted in this process, calls it directly)."""
        with self._delivery:
            old, self.state = self.state, new
            if old != new:
                for callback in list(self._callbacks):
                    callback(old, new)


class Role(object):
    """A role: ``ROLE`` (its name), ``SCHEMA`` (its params), ``layer``, ``params``, ``log``, ``guard``."""

    ROLE = SCHEMA = None

    def __init__(self, layer):
        self.layer, self.log, self.guard = layer, layer.logger(self.ROLE), layer.guard(self.ROLE)
        self.params = layer.params(self.ROLE, self.SCHEMA) if self.SCHEMA is not None else None

    def follow(self, diagnosis=None):
        """``_on_state(old, new)``, ``_new_mission()`` follow the mission; ``_diagnose``: ``diagnosis``."""
        for name, register in (('_on_state', self.layer.mission.on_change),
                               ('_new_mission', self.layer.mission.on_new_mission)):
            if hasattr(self, name):
                register(self.guard(getattr(self, name)))
        if diagnosis:
            self.layer.diagnostics.add(diagnosis, self._diagnose)

"""The mission state as every role of a process sees it (core/mission_state.py).

:class:`MissionStateView` follows the owner's latched ``blind_navigation/state`` (any
other node's state is refused and logged; in the owner's process it is set directly,
:meth:`~MissionStateView.set_local`) and tells the roles of changes and of
``new_mission`` (:meth:`~MissionStateView.on_new_mission`).
"""
import threading

import rospy
from std_msgs.msg import String

from .. import names
from ..core import mission_state
from .common import subscribe


class MissionStateView(object):
    """Current mission state (None before any) of the owner node ``owner``
    (a node name, resolved in this node's namespace)."""

    def __init__(self, owner, guard=None):
        self.owner = rospy.resolve_name(owner)
        self.state = None
        self._lock = threading.Lock()
        self._delivery = threading.RLock()      # one change delivered at a time, in order
        self._callbacks = []
        self._subscriber = subscribe(names.STATE, String,
                                     guard(self._on_state) if guard else self._on_state,
                                     queue_size=10)

    def on_change(self, callback):
        """Call ``callback(old, new)`` on every change of state, from the thread that saw it,
        and at once with ``(None, state)`` if the state is known already: a role learns the
        state it starts in however its construction and the (latched) state message raced
        (a node restarted mid-mission, e.g. rotate_pi while ``rotating``, must know it)."""
        with self._delivery:
            with self._lock:
                self._callbacks.append(callback)
                current = self.state
            if current is not None:
                callback(None, current)

    def on_new_mission(self, callback):
        """Call ``callback()`` when ``new_mission`` starts the next mission (a terminal state
        -> ``idle``, core/mission_state.starts_new_mission): the roles start afresh."""
        self.on_change(lambda old, new: mission_state.starts_new_mission(old, new) and callback())

    def set_local(self, new):
        """The owner, hosted in this process, moved the mission to ``new``."""
        self._change(new)

    def _on_state(self, msg):
        sender = msg._connection_header.get('callerid', '?')
        if sender != self.owner and sender != rospy.get_name():
            rospy.logwarn_throttle(5.0, '%s: mission state %r from %s refused: only %s owns the '
                                   'mission state' % (rospy.get_name(), msg.data, sender, self.owner))
            return
        if msg.data not in mission_state.ALL:
            rospy.logwarn_throttle(5.0, '%s: unknown mission state %r from %s refused'
                                   % (rospy.get_name(), msg.data, sender))
            return
        self._change(msg.data)

    def _change(self, new):
        with self._delivery:
            with self._lock:
                old, self.state = self.state, new
                callbacks = list(self._callbacks)
            if old != new:
                for callback in callbacks:
                    callback(old, new)

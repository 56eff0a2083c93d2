"""The operator's takeover, watched once per process (core/pause.Takeover; docs/safety.md,
"Takeover"): another node's command on the mux input, a ``takeover_inputs`` input active, or
a moving command on the mux output this process did not send (not while docking).
"""
import threading

import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import String

from .. import names
from ..core.pause import Takeover
from .common import subscribe

#: The layer's nodes that publish on its mux input, in either layout.
LAYER_NODES = ('blind_navigation', 'back_travel_server', 'rotate_pi', 'calibrate_gyro')


class TakeoverWatch(object):
    """The process's takeover watch; ``params``: takeover_wait, on_takeover, takeover_inputs."""

    def __init__(self, params, guard):
        self._takeover = Takeover(params)
        self._lock = threading.Lock()
        self._own = set(rospy.resolve_name(node) for node in LAYER_NODES) | {rospy.get_name()}
        self._base = True           # the mux output is read (not while docking)
        subscribe(names.CMD_VEL, Twist, guard(self._on_command), queue_size=10)
        subscribe(names.CMD_VEL_MUX_ACTIVE, String, guard(self._on_mux), queue_size=10)
        subscribe(names.MUX_OUTPUT, Twist, guard(self._on_output), queue_size=10)

    def sent(self, v, w):
        """This process publishes (v, w) on the mux input (ros/motion.MotionOutput)."""
        with self._lock:
            self._takeover.sent(v, w, rospy.get_time())

    def watch_base(self, on):
        """Read the mux output (``on``), or not: while docking the dock drive drives it."""
        with self._lock:
            self._base = bool(on)

    def _on_output(self, msg):
        with self._lock:
            if not self._base:
                return
            self._takeover.at_base(msg.linear.x, msg.angular.z, rospy.get_time(),
                                   rospy.resolve_name(names.MUX_OUTPUT))

    def _on_command(self, msg):
        caller = msg._connection_header.get('callerid', '?')
        if caller not in self._own:
            with self._lock:
                self._takeover.command(caller, rospy.get_time())

    def _on_mux(self, msg):
        with self._lock:
            self._takeover.mux_active(msg.data, rospy.get_time())

    def active(self):
        """Why an operator holds the robot now, or None."""
        with self._lock:
            return self._takeover.active(rospy.get_time())

    def paused(self):
        """s paused by takeovers so far."""
        with self._lock:
            self._takeover.active(rospy.get_time())
            return self._takeover.paused(rospy.get_time())

"""What the roles hosted in one process share (:class:`Layer`: params, logs, odometry, the
mission state, safety, heading correction, takeover, diagnostics, guards); ``Role(layer)``."""
import threading

import rospy

from .. import names
from ..core.mission_state import IDLE, RECORDING, starts_new_mission
from ..core.geometry import OdomState
from ..core.heading_correction import GyroCorrection
from ..core.files import FileContentError
from blind_navigation.msg import HeadingCorrection
from std_msgs.msg import String
from .common import RoleLog, subscribe
from .diagnostics import Diagnostics
from . import faults
from .mission import MissionStateView
from .motion import SafetyMonitor, TakeoverWatch
from .odometry import OdometryFeed

#: The mission state's owner in the paper layout; the param of the mission's id.
MISSION_OWNER = 'back_travel_client'
MISSION_ID = 'blind_navigation/mission_id'


class Layer(object):
    """The roles' shared context; ``compact``: several roles in this process (``~<role>/`` params)."""

    def __init__(self, compact=False):
        self.compact = compact
        self.node = rospy.get_name()
        owner = self.node if compact else rospy.get_param('~mission_owner', MISSION_OWNER)
        self.mission_owner = rospy.resolve_name(owner)
        self.mission_id = rospy.get_param(MISSION_ID, None)
        self.diagnostics = Diagnostics(rospy.get_namespace().strip('/'))
        self.faults = faults.Faults(self.diagnostics)
        self.guard = self.faults.guard      # guard(role)(fn): fn whose exception fails role
        failure_pub = rospy.Publisher(names.ROLE_FAILURE, String, queue_size=5, latch=True)
        faults.on_fault(lambda fault: failure_pub.publish(String(data=fault)))  # other processes
        self.diagnostics.guard = self.guard('diagnostics')      # fails like a role
        self.odometry = OdometryFeed(names.ODOM, guard=self.guard('odometry feed'),
                                     frame_topic=None if compact else names.ODOMETRY_FRAME)
        self.visual_odometry = OdometryFeed(names.VO_ODOM, checked=False,
                                            guard=self.guard('visual odometry feed'))
        self.mission = MissionStateView(self.mission_owner, self.guard('mission state view'))
        # a new mission (and its recording) starts on the odometry as it finds it
        self.mission.on_change(self.guard('odometry feed')(lambda old, new: self.odometry.set_correction(
            None, None) if starts_new_mission(old, new) or (old, new) == (IDLE, RECORDING) else None))
        self.safety = SafetyMonitor(self.guard('safety monitor'))
        self._correction = self._takeover = None
        self._correction_lock = threading.Lock()

    def params(self, role, schema):
        """``role``'s params, typed by ``schema``; ``~<role>/name`` when compact (not the shared ones)."""
        def prefix(name):
            return '~' if not self.compact or name in schema.shared else '~%s/' % role
        values = {p.name: rospy.get_param(prefix(p.name) + p.name) for p in schema.params
                  if rospy.has_param(prefix(p.name) + p.name)}
        typed = schema.validate(values, prefix)
        rospy.loginfo('%s params%s: %s', rospy.get_name(), '' if prefix('') == '~' else ' ' + prefix(''),
                      ', '.join('%s=%r' % (p.name, getattr(typed, p.name)) for p in schema.params))
        return typed

    def current_mission_id(self):
        """The mission id, read again (``new_mission`` sets it before the roles see ``idle``)."""
        self.mission_id = rospy.get_param(MISSION_ID, self.mission_id)
        return self.mission_id

    def logger(self, role):
        """A RoleLog naming the node (and the role when compact)."""
        return RoleLog('%s/%s' % (self.node, role) if self.compact else self.node)

    def takeover(self, params):
        """The process's TakeoverWatch, made from the first caller's ``params``."""
        with self._correction_lock:
            if self._takeover is None:
                self._takeover = TakeoverWatch(params, self.guard('takeover watch'))
            return self._takeover

    def heading_correction(self):
        """The process's CorrectionReceiver."""
        with self._correction_lock:
            if self._correction is None:
                guard = self.guard('heading correction receiver')
                self._correction = CorrectionReceiver(self.odometry, guard)
                self.mission.on_new_mission(guard(self._correction.forget))
            return self._correction


def correction_from_message(msg):
    """(core GyroCorrection, raw reference OdomState) of a blind_navigation/HeadingCorrection."""
    correction = GyroCorrection(msg.bias, msg.scale, msg.bias_std, msg.scale_std, msg.windows,
                                msg.status, msg.reason)
    reference = OdomState(msg.reference_x, msg.reference_y, msg.reference_yaw, 0.0, 0.0,
                          msg.header.stamp.to_sec())
    return correction, reference


def start_roles(role_classes, compact=False):
    """The roles of this process, built in order; a bad param or file: logged fatal, exit 1."""
    layer, roles = Layer(compact), []
    for role_class in role_classes:
        try:
            roles.append(role_class(layer))
        except (ValueError, FileContentError, OSError) as error:
            rospy.logfatal('%s: %s: %s', rospy.get_name(), role_class.ROLE, error)
            raise SystemExit(1)
    return roles


def run_roles(roles):
    """Each role's ``run()``, if any, in its own guarded thread; spin until shutdown."""
    for role in roles:
        if hasattr(role, 'run'):
            threading.Thread(target=role.guard(role.run), name=role.ROLE, daemon=True).start()
    rospy.spin()


def run_node(name, role_class):
    """The paper layout's node ``name``: ``role_class`` alone in its process, until shutdown."""
    rospy.init_node(name)
    run_roles(start_roles([role_class]))


class CorrectionReceiver(object):
    """The mission's latched HeadingCorrection (the first since :meth:`forget`) set in ``odometry``."""

    def __init__(self, odometry, guard):
        self.odometry, self.received, self._lock = odometry, False, threading.Lock()
        subscribe(names.HEADING_CORRECTION, HeadingCorrection, guard(self._on_correction), queue_size=1)

    def _on_correction(self, msg):
        with self._lock:
            if not self.received:       # one correction per mission
                self.odometry.set_correction(*correction_from_message(msg))
                self.received = True

    def forget(self):
        """A new mission: the raw frame until its correction arrives."""
        with self._lock:
            self.received = False

"""What the roles hosted in one process share; a *role* is built as ``Role(layer)``.

:meth:`Layer.params` (validated against the role's schema), :meth:`Layer.logger`,
:attr:`Layer.odometry` / :attr:`Layer.visual_odometry` (one shared feed each),
:attr:`Layer.mission`, :attr:`Layer.safety`, :meth:`Layer.heading_correction`,
:meth:`Layer.takeover`, :attr:`Layer.diagnostics` and :meth:`Layer.guard` (docs/DESIGN.md).
"""
import threading

import rospy

from .. import names
from ..core.mission_state import IDLE, RECORDING
from ..core.geometry import OdomState
from ..core.heading_correction import GyroCorrection
from ..core.files import FileContentError
from blind_navigation.msg import HeadingCorrection
from std_msgs.msg import String
from .common import subscribe
from .diagnostics import Diagnostics
from . import faults
from .faults import Faults
from .mission import MissionStateView
from .motion import SafetyMonitor
from .odometry import OdometryFeed
from .takeover import TakeoverWatch

#: The node that owns the mission state when back_travel_client runs as its own node.
MISSION_OWNER = 'back_travel_client'
#: The param holding the mission's id (blind_navigation.launch sets it to $(anon mission)).
MISSION_ID = 'blind_navigation/mission_id'


class RoleLog(object):
    """rospy logging with the role's name in every line."""

    def __init__(self, prefix):
        self.prefix = prefix + ': '

    def info(self, text, *args):
        rospy.loginfo(self.prefix + text, *args)

    def warn(self, text, *args):
        rospy.logwarn(self.prefix + text, *args)

    def error(self, text, *args):
        rospy.logerr(self.prefix + text, *args)

    def warn_throttle(self, period, text, *args):
        rospy.logwarn_throttle(period, self.prefix + (text % args if args else text))


class Layer(object):
    """Shared context of the roles of one process; ``compact``: several roles in
    this process (params under ``~<role>/``)."""

    def __init__(self, compact=False):
        self.compact = compact
        self.node = rospy.get_name()
        owner = self.node if compact else rospy.get_param('~mission_owner', MISSION_OWNER)
        self.mission_owner = rospy.resolve_name(owner)
        #: This mission's id: the same for every restart of a node within one launch of the
        #: layer, new for each launch (the recorder continues its file, the client its return).
        self.mission_id = rospy.get_param(MISSION_ID, None)
        namespace = rospy.get_namespace().strip('/')
        self.diagnostics = Diagnostics(namespace or 'none')
        self.faults = Faults(self.diagnostics)
        failure_pub = rospy.Publisher(names.ROLE_FAILURE, String, queue_size=5, latch=True)
        faults.on_fault(lambda fault: failure_pub.publish(String(data=fault)))  # other processes
        # what the roles share fails like a role, under its own name
        self.diagnostics.guard = self.guard('diagnostics')
        # one process: one feed; the paper's layout: the nodes share a reset's frame
        self.odometry = OdometryFeed(names.ODOM, guard=self.guard('odometry feed'),
                                     frame_topic=None if compact else names.ODOMETRY_FRAME)
        self.visual_odometry = OdometryFeed(names.VO_ODOM, checked=False,
                                            guard=self.guard('visual odometry feed'))
        self.mission = MissionStateView(self.mission_owner, self.guard('mission state view'))
        # a new mission starts on the odometry as it finds it (ros/odometry.py), and so does
        # its recording: a reset while idle (a restarted simulator's clock) loses nothing
        self.mission.on_new_mission(self.guard('odometry feed')(
            lambda: self.odometry.set_correction(None, None)))
        self.mission.on_change(self.guard('odometry feed')(
            lambda old, new: self.odometry.set_correction(None, None)
            if (old, new) == (IDLE, RECORDING) else None))
        self.safety = SafetyMonitor(self.guard('safety monitor'))
        self._correction = None
        self._correction_lock = threading.Lock()
        self._takeover = None

    def params(self, role, schema):
        """The params of ``role`` (a name), typed and frozen by its ``schema``
        (core/params.Schema); a ParamError (ValueError) names a bad one. Hosted with
        other roles, a role's params are ``~<role>/name``, except the schema's shared
        ones that several roles read (e.g. ``straight_rate``): ``~name`` for the process."""
        def prefix(name):
            return '~' if not self.compact or name in schema.shared else '~%s/' % role
        values = {p.name: rospy.get_param(prefix(p.name) + p.name) for p in schema.params
                  if rospy.has_param(prefix(p.name) + p.name)}
        typed = schema.validate(values, prefix)
        rospy.loginfo('%s params%s: %s', rospy.get_name(), '' if prefix('') == '~' else ' ' + prefix(''),
                      ', '.join('%s=%r' % (p.name, getattr(typed, p.name)) for p in schema.params))
        return typed

    def current_mission_id(self):
        """The mission id, read again: ``new_mission`` sets a new one before the roles see
        ``idle`` (ros/mission_owner.py)."""
        self.mission_id = rospy.get_param(MISSION_ID, self.mission_id)
        return self.mission_id

    def guard(self, role):
        """``guard(fn)``: ``fn`` whose unexpected exception fails ``role``: zero velocity,
        the mission ``aborted`` naming it, diagnostics ERROR (ros/faults.py). Every thread
        target and callback a role registers goes through it."""
        return self.faults.guard(role)

    def logger(self, role):
        """A RoleLog naming the node, and the role when it shares the node."""
        return RoleLog('%s/%s' % (self.node, role) if self.compact else self.node)

    def takeover(self, params):
        """The process's TakeoverWatch (created at the first call, from that role's
        ``params``: takeover_wait, on_takeover, takeover_inputs, shared by the process)."""
        with self._correction_lock:
            if self._takeover is None:
                self._takeover = TakeoverWatch(params, self.guard('takeover watch'))
            return self._takeover

    def heading_correction(self):
        """The process's receiver of the latched heading correction (created at the
        first call: only the roles that drive on it subscribe)."""
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
    """Build the roles (classes taking the Layer) of this process, in order, after
    ``rospy.init_node``; a bad param (ValueError) or a file a role cannot use (e.g. a
    ``landmark_file`` that is a directory: core/files.FileContentError, OSError) is logged
    as fatal, naming it, and exits with status 1. Returns the roles (a list with the
    ``layer`` they share); :func:`run_roles` runs them."""
    layer = Layer(compact)
    roles = Roles()
    roles.layer = layer
    for role_class in role_classes:
        try:
            roles.append(role_class(layer))
        except (ValueError, FileContentError, OSError) as error:
            rospy.logfatal('%s: %s: %s', rospy.get_name(), role_class.ROLE, error)
            raise SystemExit(1)
    return roles


class Roles(list):
    """The roles of a process (start_roles), with ``layer``, the Layer they share."""


def run_roles(roles):
    """Run each role's blocking ``run()`` loop (if it has one) in its own guarded thread
    (:meth:`Layer.guard`), and spin until shutdown."""
    for role in roles:
        if hasattr(role, 'run'):
            threading.Thread(target=roles.layer.guard(role.ROLE)(role.run), name=role.ROLE,
                             daemon=True).start()
    rospy.spin()


def run_node(name, role_class):
    """The paper layout's node ``name``: ``role_class`` alone in its process, until shutdown."""
    rospy.init_node(name)
    run_roles(start_roles([role_class]))


class CorrectionReceiver(object):
    """Installs the mission's latched blind_navigation/HeadingCorrection (the first one since
    :meth:`forget`) into ``odometry`` (ros/odometry.OdometryFeed.set_correction): ``received``."""

    def __init__(self, odometry, guard):
        self.odometry, self.received, self._lock = odometry, False, threading.Lock()
        subscribe(names.HEADING_CORRECTION, HeadingCorrection, guard(self._on_correction), queue_size=1)

    def _on_correction(self, msg):
        with self._lock:
            if not self.received:       # one correction per mission
                self.odometry.set_correction(*correction_from_message(msg))
                self.received = True

    def forget(self):
        """A new mission: the raw frame until its own correction arrives (the layer drops the feed's)."""
        with self._lock:
            self.received = False

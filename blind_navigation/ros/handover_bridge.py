"""closed_loop between two goals (issue 29): the return's shared follower drives on
(core/goal.HandoverBridge) until the next goal comes, for at most ``handover_follow`` s,
as a drive-loop behaviour of the back-travel server; any other end halts the output.
Why: docs/evaluation.md, "Over ROS as in the harness (issue 29)".
"""
import rospy

from blind_navigation.core import drive
from blind_navigation.core.goal import HandoverBridge


def wait_while(condition, seconds):
    """Wait (ROS time) while ``condition()``, at most ``seconds`` (shutdown or the time
    moving back end the wait)."""
    deadline = rospy.get_time() + seconds
    try:
        while condition() and rospy.get_time() < deadline and not rospy.is_shutdown():
            rospy.sleep(0.02)
    except rospy.ROSInterruptException:
        return


def drive_between_goals(server, follower):
    """After a goal of ``server`` (ros/back_travel_server): the follower drives on until the
    next goal comes; then the server's hand-over hold takes over (the next goal publishes at
    once, or zero after the hold)."""
    try:
        behaviour = _Bridge(HandoverBridge(follower, server.params.handover_follow, rospy.get_time()),
                            server.hold, server.output, lambda: server._pending is not None)
        outcome = server.drive.run(behaviour, 'hand-over after goal %d' % server.next_goal,
                                   inactive=server._inactive, contacts=server.contacts)
        if not outcome.ok:
            server.log.info('hand-over after goal %d: %s', server.next_goal, outcome.reason)
        if not outcome.ok and outcome.kind != drive.TIMED_OUT:
            server.bridge_failed = outcome  # a safety stop, a contact too many: the next goal ends so
    finally:
        with server._lock:
            server._bridging = False
    server._schedule_handover()


class _Bridge(drive.Behaviour):
    """A core/goal.HandoverBridge as a drive-loop behaviour: it ends, without a halt, once
    ``arrived()`` (the next goal); when it has driven its time or the route ended, halting."""

    def __init__(self, bridge, hold, output, arrived):
        self.bridge, self.command_hold, self.output, self.arrived = bridge, hold, output, arrived

    def end(self):
        if self.arrived():
            return drive.Outcome(drive.SUCCEEDED, 'the next goal came')
        if self.bridge.ended or self.bridge.expired(rospy.get_time()):
            return drive.Outcome(drive.TIMED_OUT, 'no next goal within %.2f s: zero velocity'
                                 % (self.bridge.deadline - self.bridge.started))
        return None

    def resumed(self, seconds):
        self.bridge.follower.pause_ended()

    def step(self, odom, now):
        follower = self.bridge.follower
        self.output.limit(follower.limits[min(follower.section, len(follower.limits) - 1)])
        self.command_hold.published(now)
        return self.bridge.step(odom)

"""When the pi turn begins, for the mission's owner (ros/back_travel_client.py).

In ``rotating`` the recording goes on until the turn is committed (the bias standstill
over, or ``vision_back_grace`` s); a problem that ends the mission ends it before the
turn; at the commit the recording ends (ros/paper_adapter.RemoteTurn); vision back before it: ``recording``
again (docs/safety.md, "Vision back", "Decide before the turn").
"""
import threading
import time

import rospy
from std_msgs.msg import String

from blind_navigation import names
from blind_navigation.core import mission_state as state, outcome
from blind_navigation.core.progress import ReturnProgress
from blind_navigation.core.return_plan import frame_lost
from blind_navigation.ros.clock import LoopClock
from blind_navigation.ros.common import subscribe
from blind_navigation.ros.takeover import after_unpaused

#: s (sim) between the checks whether the turn may begin
POLL = 0.02


class TurnStart(object):
    """The turn's start and vision back for ``client`` (the BackTravelClient)."""

    def __init__(self, client):
        self.client = client
        self.lock = threading.Lock()
        self.episode = 0        # one per rotating: a late commit or timeout of an earlier one is void
        self.lost_at = None     # sim s of the vision loss behind this rotating (None: go_home)
        self.begun = False      # the turn is committed: no way back to recording
        subscribe(names.VISION_BACK, String, client.guard(self.on_vision_back), queue_size=5)

    def begin(self, reason, vision):
        """Recording -> rotating for ``reason`` (``vision``: a vision loss). True if it moved."""
        c = self.client
        with self.lock:
            if c.state != state.RECORDING:
                return False
            problem = self._problem()
            if problem:
                c.move(state.RECORDING, state.ABORTED, '%s, but %s' % (reason, problem.reason),
                       problem.code)
                return False
            if not c.move(state.RECORDING, state.ROTATING, reason):
                return False
            self.episode += 1
            self.begun, self.lost_at = False, rospy.get_time() if vision else None
            episode = self.episode
        threading.Thread(target=c.guard(self._commit_when_ready), args=(episode,),
                         name='turn_start', daemon=True).start()
        # the turn's timeout counts no time an operator's takeover paused it
        after_unpaused(c.rotation_timeout, c.takeover, c.guard(lambda: self._check_rotation(episode)),
                       'the pi turn timeout')
        return True

    def forget(self):
        """A new mission: a commit or a turn timeout still pending is void."""
        with self.lock:
            self.episode += 1
            self.begun, self.lost_at = False, None

    def _ready(self):
        correction = self.client.correction
        if correction is not None:
            return correction.received
        grace = self.client.params.vision_back_grace if self.lost_at is not None else 0.0
        return rospy.get_time() >= (self.lost_at or 0.0) + grace

    def _commit_when_ready(self, episode):
        """Wait (sim time) until the turn may begin, then commit it: the anchor and the
        progress saved, the recording ended. Void if the mission left this rotating."""
        c = self.client
        clock = LoopClock('waiting for the pi turn to begin', c.log)
        while True:
            with self.lock:
                if rospy.is_shutdown() or episode != self.episode or c.state != state.ROTATING:
                    return
                if self._ready():
                    problem = self._problem()
                    if problem:
                        c.move(state.ROTATING, state.ABORTED, 'before the pi turn: %s'
                               % problem.reason, problem.code)
                        return
                    self.begun = True
                    self._save_anchor()
                    break
            try:
                clock.sleep(POLL)   # the time moving back ends the mission (BackTravelClient)
            except rospy.ROSInterruptException:
                return
        c.remote_turn.begin()
        c.log.info('the pi turn begins: recording ended')

    def _problem(self):
        """What already ends the mission, asked before the standstill and again before the
        turn (lock held), a core/outcome.Ending: the odometry's frame lost, or a recording
        that gives no way back (core/return_plan.recording_problem); None if the return can go on."""
        c = self.client
        lost = c.lost or c.odometry.lost
        if lost:
            return outcome.Ending(outcome.ODOMETRY, frame_lost(lost))
        return c.runner.recording_problem()

    def _save_anchor(self):
        """Where the recording stopped: the return's anchor, the turn's start yaw (lock held)."""
        c = self.client
        latest = c.odometry.latest()
        anchor = [latest.x, latest.y] if latest is not None else None
        c.turn_start = latest.yaw if latest is not None else None
        c.recording_ended = latest.stamp if latest is not None else None
        c.keeper.save(ReturnProgress.begin(c.landmark_file, anchor, c.odometry.frame_id,
                                           time.time(), c.layer.mission_id))
        if c.state != state.ROTATING:   # a fault ended the mission meanwhile
            c.keeper.save(c.keeper.progress.finish(state.ABORTED, c.reason, time.time()))

    def _check_rotation(self, episode):
        if episode == self.episode:
            self.client.move(state.ROTATING, state.ABORTED, 'no finished pi turn within %.0f s '
                             'of vision loss (is rotate_pi running?)' % self.client.rotation_timeout,
                             outcome.TIMEOUT)

    def on_vision_back(self, msg):
        """Vision back: ``recording`` again before the turn, else ``on_vision_back``."""
        c = self.client
        with self.lock:
            current = c.state
            if current == state.ROTATING and self.lost_at is None:
                return          # go_home: the return was asked for, not forced by the loss
            new = state.vision_back_state(current, self.begun, c.params.on_vision_back)
            if new == state.RECORDING:
                lost = rospy.get_time() - self.lost_at
                if c.move(state.ROTATING, state.RECORDING, 'brief vision loss, %s (%.1f s after the '
                          'loss was noticed): the mission goes on in %s' % (msg.data, lost,
                                                                           c.landmark_file)):
                    self.episode += 1
                    self.lost_at = None
                return
        if new is None:
            c.log.info('%s: the mission is %s, on_vision_back %s', msg.data, current,
                       c.params.on_vision_back)
            return
        left = c.runner.distance_left()
        where = 'the pi turn' if current == state.ROTATING else 'the return'
        if c.move(current, state.RECOVERED, '%s during %s: stopped (on_vision_back stop), %s left '
                  'to home' % (msg.data, where, 'the whole path' if left is None
                               else '%.2f m' % left), outcome.VISION_BACK):
            c.runner.cancel()

"""The mission's recording, standstill and pi turn when other nodes do them (the paper's layout),
fed by its owner through :class:`Remote` (``Mission(remote=Remote(...))``). docs/DESIGN.md,
"The paper's layout".
"""
from . import outcome
from .allowance import DRIVE
from .battery import BatteryWatch
from .drive import DriveCycle
from .heading_correction import no_correction
from .mission_drive import DONE, PiTurn
from .rotation import turn_problem


class Remote(object):
    """What the owner hears of the other nodes: :meth:`reported` (the saver's distance), ``measured``
    (heading_correction's correction, awaited if ``awaits_correction``). Itself the standstill."""

    def __init__(self, awaits_correction):
        self.fit = True if awaits_correction else None
        self.measured, self.current, self.refused = None, None, ''

    def reported(self, distance):
        if self.current is not None:
            self.current.reported, self.current.distance = True, distance

    def recording(self, *_args):
        self.current, self.measured = RemoteRecording(), None
        return self.current

    def standstill(self, *_args):
        return self

    def correction(self, now, odom=None):
        return self.measured if self.fit else no_correction('heading correction off')

    def turn(self, params, feed, odom, config, clock):
        return RemoteTurn(self, params, feed, odom, config, clock)


class RemoteRecording(object):
    """MissionRecording's part for a recording made elsewhere (``lost``: an untrusted reset)."""
    fit, requested = None, ()

    def __init__(self):
        self.start = self.lost = None
        self.distance, self.reported, self.battery = 0.0, False, BatteryWatch(0.0)

    started = property(lambda self: self.start is not None)

    def begin(self, odom):
        self.start = (odom.x, odom.y)

    def step(self, *_args):
        """No landmarks here (the saver stores them), no fit (heading_correction's), no resuming
        (the sampling publisher goes on by itself)."""
        return []

    end = feed = resume = step

    def reset(self, odom, reason):
        self.lost = self.lost or reason


class RemoteTurn(PiTurn):
    """rotate_pi's turn: done once ``Inputs.goal_result`` says it ended well and the robot
    really turned (else refused, the reason in ``remote.refused``)."""

    def __init__(self, remote, params, feed, odom, config, clock):
        PiTurn.__init__(self, params, feed, odom, config, clock)
        self.remote, self.cycle = remote, DriveCycle(params)

    def resumed(self, seconds):
        self.clock.resumed(seconds)

    def step(self, now, inputs):
        decision, odom, _ = self.feed(self.cycle)
        self.yaw = odom.yaw if decision == DRIVE else self.yaw
        result = inputs.goal_result
        if self.clock.elapsed(now) > self.timeout:
            self._fail(outcome.TIMEOUT, 'no finished pi turn within %.0f s of vision loss (is rotate_pi '
                       'running?)' % self.timeout)
        elif result is not None and not result.ok:
            self._fail(result.cause or outcome.TURN, result.reason)
        elif result is not None:
            self.remote.refused = turn_problem(self.start_yaw, self.yaw, self.tolerance)
            self.phase = DONE if not self.remote.refused else self.phase
        return None

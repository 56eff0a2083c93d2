"""The return's ending, after its last goal: the robot settles (stopped, or ``settle_time``
s); then the home verdict (core/mission_drive.home_verdict, the only place that declares
``home``). :class:`ReturnEnding` is stepped by core/mission.Mission. docs/safety.md,
"`home`: one invariant".
"""
from .back_travel import BACK_TRAVEL_DEFAULTS, stopped
from .mission_drive import ZERO, home_verdict

SETTLE, APPROACH = 'settle', 'final approach'


class ReturnEnding(object):
    """The return's ending from ``now`` (module docstring): ``goals`` driven, ``route`` (None: the
    paper's modes, position not checked), the return's ``warning``; ``odom()``: the latest
    odometry."""

    def __init__(self, now, params, config, route, goals, warning, feed, odom, approach=True):
        self.params, self.config, self.route, self.goals, self.warning = params, config, route, goals, warning
        self.feed, self.odom = feed, odom
        self.phase, self.until = SETTLE, now + config.settle_time

    def where(self):
        return 'the final approach'

    def resumed(self, seconds):
        """A pause of ``seconds`` ended."""

    def step(self, now):
        """(command, verdict): the command this cycle (None: nothing); the verdict, (state, core/
        outcome code, reason) once the mission ends, else None."""
        odom = self.odom()
        if not stopped(odom) and now < self.until - 1e-9:
            return None, None
        return ZERO, home_verdict(odom, self.route, self.goals, self.config.mode, getattr(
            self.params, 'home_tolerance', BACK_TRAVEL_DEFAULTS['home_tolerance']), self.warning)

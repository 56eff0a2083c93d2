"""The mission's allowances beyond its drives' own: the pi turn's from vision loss
(:func:`rotation_timeout`) and a return's (:class:`ReturnWatch`); paused time not counted.
"""
from .gyro_bias import standstill_timeout
from .outcome import TIMEOUT, Ending
from .plausibility import RouteBudget
from .role_params import BACK_TRAVEL_CLIENT
from .safety import expected_duration, return_allowance

#: The back_travel_client's params these allowances read (its defaults).
LIMIT_DEFAULTS = dict(
    {name: BACK_TRAVEL_CLIENT.fixed[name]
     for name in ('rotation_margin', 'goal_timeout_factor', 'goal_timeout_margin', 'slowest_v')},
    **{name: BACK_TRAVEL_CLIENT[name].default
       for name in ('return_timeout_factor', 'return_timeout_margin', 'vision_back_grace')})


def with_defaults(params, defaults):
    """An object with ``defaults``' attributes, each ``params``' own where it has one."""
    return type('Params', (), {name: getattr(params, name, value) for name, value in defaults.items()})


def rotation_timeout(params, config):
    """s from vision loss to the pi turn's end: the standstill's timeout + rotation_margin (the
    ``config``'s limits, else ``params``) + vision_back_grace."""
    margin = with_defaults(config.limits or params, LIMIT_DEFAULTS).rotation_margin
    return standstill_timeout(config.standstill) + margin + config.vision_back_grace


class PausedClock(object):
    """Seconds since ``start`` without the pauses :meth:`update` reports."""

    def __init__(self, start):
        self.start, self.paused, self.paused_at = start, 0.0, None

    def update(self, now, paused):
        """This cycle at ``now``: ``paused`` or not; True while paused."""
        if paused:
            self.paused += now - self.paused_at if self.paused_at is not None else 0.0
            self.paused_at = now
        else:
            self.paused_at = None
        return bool(paused)

    def resumed(self, seconds):
        """A pause of ``seconds`` ended (one its owner measured)."""
        self.paused += seconds

    def elapsed(self, now):
        return now - self.start - self.paused


class ReturnWatch(object):
    """The limits of one return from ``now`` over ``landmarks`` (all: the distance budget),
    ``remaining`` of them to drive (the time allowance); ``params``: :data:`LIMIT_DEFAULTS`' names.
    :meth:`goal` at each remote goal's start (its backstop), :meth:`problem` each cycle."""

    def __init__(self, landmarks, remaining, params, now):
        self.p = with_defaults(params, LIMIT_DEFAULTS)
        self.allowance = return_allowance(remaining, self.p.return_timeout_factor,
                                          self.p.return_timeout_margin, self.p.slowest_v)
        self.clock = PausedClock(now)
        self.budget = RouteBudget(landmarks)
        self.goal_allowance = self.last_heard = None

    def goal(self, landmark, now):
        """A goal over ``landmark`` starts at ``now``: its backstop counts from here."""
        self.goal_allowance = (self.p.goal_timeout_factor * expected_duration(landmark, self.p.slowest_v)
                               + self.p.goal_timeout_margin)
        self.last_heard = now

    def update(self, now, paused):
        """This cycle: ``paused`` (a takeover, a bumper press) counts against no allowance."""
        if self.clock.update(now, paused):
            self.last_heard = now

    def resumed(self, seconds):
        """A pause of ``seconds`` ended: not counted; the goal's backstop counts afresh."""
        self.clock.resumed(seconds)
        self.last_heard = None

    def problem(self, now, travelled):
        """The Ending (TIMEOUT) at ``now`` having driven ``travelled`` m: the goal's backstop, the
        whole return's allowance, the distance budget; else None."""
        self.last_heard = now if self.last_heard is None else self.last_heard
        if self.goal_allowance is not None and now > self.last_heard + self.goal_allowance:
            why = ('no result and no feedback for %.0f s (the goal\'s backstop: goal_timeout_factor x '
                   'its expected duration + goal_timeout_margin)' % self.goal_allowance)
        elif self.clock.elapsed(now) > self.allowance:
            why = ('the return exceeded its time allowance of %.0f s (return_timeout_factor x its '
                   'expected duration + return_timeout_margin)' % self.allowance)
        else:
            why = self.budget.problem(travelled)
        return Ending(TIMEOUT, why) if why else None

"""Kobuki's IR dock drive as kobuki_dock_drive publishes it, written again in plain Python.

:class:`DockDrive` takes, each 50 Hz cycle, the three dock IR bytes (right, central,
left), the bumper and charger of SensorState and the odometry heading, and returns the
base velocity: IDLE -> SCAN (turn until the central receiver sees the central beam, or
counting left/right beams) -> FIND_STREAM / GET_STREAM (cross to the central line) ->
ALIGNED_FAR / ALIGNED_NEAR (approach on the central receiver) -> DOCKED_IN -> DONE.
States, speeds and sources: docs/fake_turtlebot.md (The dock).
"""
import math

from ..core.geometry import wrap_angle
from .dock import FAR, FAR_CENTER, FAR_LEFT, FAR_RIGHT, NEAR, NEAR_CENTER, NEAR_LEFT, NEAR_RIGHT

PERIOD = 0.02                 # s, one cycle (the Kobuki's 50 Hz)
SIGNAL_WINDOW = 20            # cycles of IR bytes or-ed together (kobuki_dock_drive's window)
DOCK_STABILIZER = 20          # cycles on the charger before DONE
BUMP_BACK_CYCLES = 10         # cycles backing off after a bump
MIN_ABS_V, MIN_ABS_W = 0.01, 0.1  # m/s, rad/s: kobuki_auto_docking's min_abs_v, min_abs_w
SCAN_W, SLOW_W, STREAM_W = 0.66, 0.1, 0.33   # rad/s
LEFT_BEAMS, RIGHT_BEAMS = FAR_LEFT | NEAR_LEFT, FAR_RIGHT | NEAR_RIGHT
#: the central receiver's bits -> (state, v, w) while aligned, first match wins
_ALIGNED = (
    (lambda m: m & NEAR in (NEAR_CENTER, NEAR), ('ALIGNED_NEAR', 0.05, 0.0)),
    (lambda m: m & NEAR_LEFT, ('ALIGNED_NEAR', 0.05, SLOW_W)),
    (lambda m: m & NEAR_RIGHT, ('ALIGNED_NEAR', 0.05, -SLOW_W)),
    (lambda m: m & FAR in (FAR_CENTER, FAR), ('ALIGNED_FAR', 0.1, 0.0)),
    (lambda m: m & FAR_LEFT, ('ALIGNED_FAR', 0.1, 0.3)),
    (lambda m: m & FAR_RIGHT, ('ALIGNED_FAR', 0.1, -0.3)),
)


def _sign(x):
    return (x > 0) - (x < 0)


class DockDrive(object):
    """The dock drive's state machine (module docstring). ``state`` is its name as the action's
    feedback reports it; UNKNOWN is where it stops for good (no dock found: kobuki_core#55)."""

    def __init__(self):
        self.state = 'IDLE'
        self.v = self.w = 0.0
        self._signals = []
        self._dock_detector = 0    # > 0: the dock is to the robot's right side region, < 0 left
        self._rotated = 0.0        # turns scanned
        self._stabilizer = 0
        self._bumps = 0
        self.bumped = 0            # bumps (pressed without charging) since the goal began, for verdicts
        self._heading = None
        self.unseen_time = 0.0     # s driving (not turning on the spot) with no beam seen, for verdicts

    def update(self, ir, bumper, charger, heading):
        """One cycle: ``ir`` [right, central, left] bytes, SensorState ``bumper`` and
        ``charger``, odometry ``heading`` (rad). Returns (v, w) to command."""
        turn = 0.0 if self._heading is None else wrap_angle(heading - self._heading)
        self._heading = heading
        if bumper or charger:
            self._contact(bumper, charger)
        else:
            self._signals = (self._signals + [list(ir)])[-SIGNAL_WINDOW:]
            seen = [0, 0, 0]
            for sample in self._signals:
                seen = [a | b for a, b in zip(seen, sample)]
            self._step(seen, turn)
        self.unseen_time = self.unseen_time + PERIOD if self.v and not any(ir) else 0.0
        return self.v, self.w

    @property
    def done(self):
        return self.state == 'DONE'

    def _set(self, state, v, w):
        self.state = state
        self.v = _sign(v) * max(abs(v), MIN_ABS_V)
        self.w = _sign(w) * max(abs(w), MIN_ABS_W)

    def _contact(self, bumper, charger):
        if charger and bumper:
            self._set('BUMPED_DOCK', -0.01, 0.0)
        elif charger:
            self._stabilizer += 1
            if self._stabilizer > DOCK_STABILIZER:
                self._stabilizer = 0
                self._set('DONE', 0.0, 0.0)
            else:
                self._set('DOCKED_IN', 0.0, 0.0)
        else:
            self.bumped += self.state != 'BUMPED'
            self._set('BUMPED', -0.05, 0.0)
            self._bumps = 0

    def _step(self, seen, turn):
        right, mid, left = seen
        state = self.state
        if state == 'IDLE':
            self._dock_detector, self._rotated = 0, 0.0
            self._set('SCAN', 0.0, SCAN_W)
        elif state == 'SCAN':
            self._scan(mid, turn)
        elif state == 'FIND_STREAM':
            self._find_stream(right, left)
        elif state == 'GET_STREAM':
            self._get_stream(right, left)
        elif state in ('ALIGNED', 'ALIGNED_FAR', 'ALIGNED_NEAR'):
            self._aligned(mid)
        elif state == 'BUMPED':
            if self._bumps < BUMP_BACK_CYCLES:
                self._bumps += 1
                self._set('BUMPED', -0.05, 0.0)
            else:
                self._bumps = 0
                self._set('SCAN', 0.0, 0.0)
        else:                                   # UNKNOWN (and DONE, DOCKED_IN...): stand still
            self._set(state, 0.0, 0.0)

    def _scan(self, mid, turn):
        self._rotated += turn / (2.0 * math.pi)
        if mid & (FAR_CENTER | NEAR_CENTER):
            self._set('ALIGNED', 0.05, 0.0)
        elif mid & LEFT_BEAMS:
            self._dock_detector -= 1
            self._set('SCAN', 0.0, SCAN_W)
        elif mid & RIGHT_BEAMS:
            self._dock_detector += 1
            self._set('SCAN', 0.0, SCAN_W)
        elif mid:
            self._set('SCAN', 0.0, SLOW_W)
        elif abs(self._rotated) > 1.0:
            self._set('FIND_STREAM', 0.0, 0.0)
        else:
            self._set('SCAN', 0.0, SCAN_W)

    def _find_stream(self, right, left):
        if self._dock_detector > 0:             # right of the dock: turn cw until the left receiver sees the right beam
            if left & RIGHT_BEAMS:
                self._set('GET_STREAM', 0.5, 0.0)
            else:
                self._set('FIND_STREAM', 0.0, -STREAM_W)
        elif self._dock_detector < 0:           # left of the dock: ccw until the right receiver sees the left beam
            if right & LEFT_BEAMS:
                self._set('GET_STREAM', 0.5, 0.0)
            else:
                self._set('FIND_STREAM', 0.0, STREAM_W)
        else:
            self._set('UNKNOWN', 0.0, 0.0)

    def _get_stream(self, right, left):
        crossed = (self._dock_detector > 0 and left & LEFT_BEAMS) or \
                  (self._dock_detector < 0 and right & RIGHT_BEAMS)
        if crossed:
            self._dock_detector, self._rotated = 0, 0.0
            self._set('SCAN', 0.0, SLOW_W)
        elif self._dock_detector:
            self._set('GET_STREAM', 0.05, 0.0)
        else:
            self._set('UNKNOWN', 0.0, 0.0)

    def _aligned(self, mid):
        if mid:
            for matches, (state, v, w) in _ALIGNED:
                if matches(mid):
                    self._set(state, v, w)
                    return
            self._dock_detector, self._rotated = 0, 0.0
        self._set('SCAN', 0.0, SCAN_W)

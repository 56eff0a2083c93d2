"""Pauses of a return: bumper :class:`Contacts` and an operator's :class:`Takeover`, summed
up by :class:`PauseLog` (docs/safety.md, "Contacts", "Takeover")."""
import collections
import math

CONTACT_DEFAULTS = {
    'contact_wait': 2.0,        # s after a bumper release before the return goes on
    'max_contacts': 3,          # bumper contacts one return survives; the next one aborts it
    'contact_timeout': 10.0,    # s a contact may last from its first press, bounces included
}
TAKEOVER_DEFAULTS = {
    'takeover_wait': 2.0,       # s of operator silence before the layer drives again
    'on_takeover': 'resume',    # after a takeover: resume (re-track from the new pose) or abort
    'takeover_inputs': ['Safe reactive controller'],  # cmd_vel_mux inputs (names on
                                # cmd_vel_mux/active) above the layer's: active = a takeover
}
POLICIES = ('resume', 'abort')
PAUSE = 'pause'
#: s a command the layer sent is remembered, to recognise it on the mux's output (Takeover.at_base)
SENT_MEMORY = 1.0


def _positive(params, name):
    if not float(getattr(params, name)) > 0:
        raise ValueError('~%s must be positive, got %r' % (name, getattr(params, name)))


class Contacts(object):
    """Bumper contacts of one return: a press holds the robot until ``contact_wait`` s after its
    release; too many (``max_contacts``) or too long (``contact_timeout``) aborts. ``sensors``,
    ``presses``: the contact under way's bumpers and presses (bounces included)."""

    def __init__(self, params):
        _positive(params, 'contact_timeout')
        self.wait, self.timeout = float(params.contact_wait), float(params.contact_timeout)
        self.max = int(params.max_contacts)
        if self.wait < 0 or self.max < 0:
            raise ValueError('~contact_wait and ~max_contacts must not be negative')
        self.count = self.presses = 0
        self.first = self.released_at = None    # of the contact under way: its first press, last release
        self.sensors = []

    def decide(self, pressed, now, presses=None, sensors=()):
        """``pressed`` (since the last cycle) -> PAUSE, None (drive on) or the abort reason;
        ``presses``: since the last cycle (None: one if the last cycle was released)."""
        if not pressed:
            return self._released(now)
        new = self.first is None
        if new:
            self.count += 1
            self.first, self.presses, self.sensors = now, 0, []
        if presses is None:
            presses = 1 if new or self.released_at is not None else 0
        self.presses += max(presses, 1 if new else 0)
        self.released_at = None
        for name in sensors:
            if name not in self.sensors:
                self.sensors.append(name)
        if new and self.count > self.max:
            return 'bumper contact %d of at most %d (max_contacts)' % (self.count, self.max)
        if now - self.first > self.timeout:
            how = 'pressed for %.1f s' % (now - self.first) if self.presses == 1 else (
                'lasted %.1f s from its first press (%d presses, each within contact_wait %.1f s '
                'of a release)' % (now - self.first, self.presses, self.wait))
            return 'bumper contact %d %s, longer than contact_timeout %.1f s' % (
                self.count, how, self.timeout)
        return PAUSE

    def _released(self, now):
        if self.first is None:
            return None
        if self.released_at is None:
            self.released_at = now
        if now - self.released_at < self.wait:
            return PAUSE
        self.first = self.released_at = None
        return None

    def describe(self):
        return '%d of at most %d' % (self.count, self.max)


class Takeover(object):
    """Whether an operator holds the robot: another publisher on the layer's mux input, or a
    higher input active, holds it until ``takeover_wait`` s of silence."""

    def __init__(self, params):
        _positive(params, 'takeover_wait')
        if params.on_takeover not in POLICIES:
            raise ValueError('~on_takeover must be one of %s, got %r'
                             % (', '.join(POLICIES), params.on_takeover))
        self.wait, self.policy = float(params.takeover_wait), params.on_takeover
        self.inputs = [str(name) for name in params.takeover_inputs]
        self.last = None            # time of the operator's last sign (a command, a mux release)
        self.by = None              # who: the foreign publisher or the mux input
        self.holder = None          # one of takeover_inputs while the mux says it is active
        self.total = 0.0            # s paused by takeovers so far (see paused())
        self._since = None
        self._sent = collections.deque()    # (time, v, w) the layer sent, the last SENT_MEMORY s
        self._echoed = None         # when the mux's output last carried one of them

    def sent(self, v, w, now):
        """The layer sent (v, w) on its mux input (before it is published: the mux may echo it at once)."""
        self._forget(now)
        self._sent.append((now, v, w))

    def _forget(self, now):
        while self._sent and not now - SENT_MEMORY <= self._sent[0][0] <= now:
            self._sent.popleft()      # too old, or the clock moved back

    def at_base(self, v, w, now, output):
        """The mux forwarded (v, w) to the base (on ``output``): a moving command the layer did not
        send, while the layer drives and the output echoes its commands, is an operator's."""
        self._forget(now)
        if any((v, w) == (sent_v, sent_w) for _, sent_v, sent_w in self._sent):
            self._echoed = now
            return
        driving = any(sent_v or sent_w for _, sent_v, sent_w in self._sent)
        echoing = self._echoed is not None and 0.0 <= now - self._echoed <= SENT_MEMORY
        if driving and echoing and (v or w):
            self.command('a command on %s the layer did not send' % output, now)

    def command(self, caller, now):
        """Another publisher's command on the layer's own input."""
        self.last, self.by = now, caller

    def mux_active(self, name, now):
        """The mux announced ``name`` active."""
        if name in self.inputs:
            self.holder, self.by = name, 'cmd_vel_mux input %s' % name
        elif self.holder is not None:
            self.holder, self.last = None, now

    def active(self, now):
        """Why the operator holds the robot now, or None."""
        if self.holder is not None or (self.last is not None and now - self.last < self.wait):
            if self._since is None:
                self._since = now
            return 'operator takeover by %s' % self.by
        if self._since is not None:
            self.total += now - self._since
            self._since = None
        return None

    def paused(self, now):
        """s paused by takeovers so far, the one under way included."""
        return self.total + (now - self._since if self._since is not None else 0.0)


class PauseLog(object):
    """The pauses of one return for the owner's status and final reason: takeovers (how many,
    how long, how far moved) and contacts (presses less than ``contact_wait`` s apart are one)."""

    def __init__(self, contact_wait):
        self.wait = float(contact_wait)
        self.takeovers = []         # [start s, end s or None, moved m or None]
        self.contacts = []          # [first press s, last release s or None]
        self._taken_at = None       # the position [x, y] where the takeover under way began

    def update(self, now, taken, pressed, position):
        """``taken`` (a takeover under way), ``pressed`` (a bumper is), ``position()``: [x, y] or None."""
        open_takeover = bool(self.takeovers) and self.takeovers[-1][1] is None
        if taken and not open_takeover:
            self.takeovers.append([now, None, None])
            self._taken_at = position()
        elif not taken and open_takeover:
            here = position()
            moved = None if here is None or self._taken_at is None else math.hypot(
                here[0] - self._taken_at[0], here[1] - self._taken_at[1])
            self.takeovers[-1][1:] = [now, moved]
        last = self.contacts[-1] if self.contacts else None
        if pressed:
            if last is None or (last[1] is not None and now - last[1] >= self.wait):
                self.contacts.append([now, None])
            else:
                last[1] = None
        elif last is not None and last[1] is None:
            last[1] = now

    def describe(self, now):
        """'' or e.g. '1 operator takeover (90.0 s, moved the robot 4.50 m); 2 bumper contacts (3.1 s)'."""
        parts = []
        if self.takeovers:
            moved = [t[2] for t in self.takeovers if t[2] is not None]
            parts.append('%d operator takeover%s (%.1f s%s)' % (
                len(self.takeovers), '' if len(self.takeovers) == 1 else 's',
                sum((t[1] if t[1] is not None else now) - t[0] for t in self.takeovers),
                ', moved the robot %.2f m' % sum(moved) if moved else ''))
        if self.contacts:
            parts.append('%d bumper contact%s (%.1f s)' % (
                len(self.contacts), '' if len(self.contacts) == 1 else 's',
                sum((c[1] if c[1] is not None else now) - c[0] for c in self.contacts)))
        return '; '.join(parts)

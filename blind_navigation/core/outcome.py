"""The mission's outcome code per cause of a terminal state (as MissionStatus's ``OUTCOME_*``),
:data:`NONE` until it ends (docs/safety.md, "Outcome codes")."""
import collections

NONE = 0                # not terminal (idle, recording, rotating, returning)
# state home
HOME = 1                # the return arrived (the home invariant; the paper's modes: replayed)
NOTHING_TO_RETRACE = 2  # a return asked for before the robot moved: home without a turn
DOCKED = 3              # with dock_at_home: docked on the charger (state docked)
DOCK_FAILED = 4         # with dock_at_home: the dock not reached (state home)
# state recovered
VISION_BACK = 10        # vision back during the turn or the return (on_vision_back stop)
# state aborted
CANCELLED = 20          # the cancel service (or the action's cancel)
CONTACTS = 21           # bumper contacts: too many, too long, or a bumper in the pi turn
SAFETY_EVENT = 22       # a cliff or a wheel drop
TAKEOVER = 23           # an operator's takeover with on_takeover abort
ODOMETRY = 24           # odometry lost (stale), reset untrusted, or implausible
CLOCK = 25              # the ROS time moved back
STORAGE = 26            # landmarks not written (beyond a standstill) or the file unreadable
WIRING = 27             # a topic of the wrong type
TIMEOUT = 28            # an allowance: the turn's, a goal's, the return's; a stall; the budget
TURN = 29               # the pi turn ended off pi or failed
OFF_ROUTE = 30          # the robot off its route (pushed off, moved while paused)
NOT_HOME = 31           # every goal done but the robot stopped out of tolerance of the start
RECORDING = 32          # the recording gives no way back (no route can be built from it)
RESUME = 33             # a restarted layer cannot resume the return a previous run left
ROLE_FAILURE = 34       # a role of the layer failed (an exception), here or in another process

#: code -> name, in code order.
NAMES = collections.OrderedDict(sorted(
    (value, name) for name, value in dict(globals()).items()
    if name.isupper() and isinstance(value, int)))


Ending = collections.namedtuple('Ending', 'code reason')
Ending.__doc__ = 'Why a mission ends: ``code`` (a constant above) and ``reason`` (the sentence).'


def describe(code):
    """'NAME (number)', e.g. 'CANCELLED (20)'; an unknown code: 'UNKNOWN (n)'."""
    return '%s (%d)' % (NAMES.get(code, 'UNKNOWN'), code)


def phrase(code, reason):
    """The final log line's tail: 'reason [outcome NAME (n)]' (a terminal code), else ``reason``."""
    return '%s [outcome %s]' % (reason, describe(code)) if code else reason

"""cmd_vel multiplexer with yocs_cmd_vel_mux's rules and TurtleBot's configuration.

An input's message is forwarded if no input holds the output, it holds it, or it has a
strictly higher priority than the holder, which it then becomes (announced on the active
topic); the holder releases after its ``timeout`` of silence (``idle``). yocs's general
timer never changes the outcome and is not modelled.
"""
from collections import namedtuple

MuxInput = namedtuple('MuxInput', 'name topic timeout priority')
IDLE = 'idle'

#: turtlebot_bringup/param/mux.yaml
TURTLEBOT_INPUTS = (
    MuxInput('Safe reactive controller', 'safety_controller', 0.2, 10),
    MuxInput('Teleoperation', 'teleop', 1.0, 7),
    MuxInput('Switch', 'switch', 1.0, 6),
    MuxInput('Navigation', 'navi', 1.0, 5),
)


def inputs_from_list(items, where='~subscribers'):
    """MuxInput tuple from dicts with name, topic, timeout, priority (yocs's YAML layout)."""
    result = []
    for i, item in enumerate(items):
        try:
            entry = MuxInput(str(item['name']), str(item['topic']), float(item['timeout']), int(item['priority']))
        except (KeyError, TypeError, ValueError) as error:
            raise ValueError('%s[%d]: needs name, topic, timeout, priority (%s)' % (where, i, error))
        if entry.timeout <= 0:
            raise ValueError('%s[%d]: timeout must be > 0, got %r' % (where, i, entry.timeout))
        result.append(entry)
    if len({e.priority for e in result}) != len(result):
        raise ValueError('%s: priorities must be unique' % where)
    return tuple(result)


class CmdVelMux(object):
    """Decides which input holds the output; times are seconds on any one clock."""

    def __init__(self, inputs=TURTLEBOT_INPUTS):
        if not inputs:
            raise ValueError('cmd_vel mux needs at least one input')
        self.inputs = tuple(inputs)
        self.allowed = None                   # index of the holder, None = vacant
        self._last = [None] * len(self.inputs)

    @property
    def active_name(self):
        """Name of the input holding the output, or 'idle'."""
        return IDLE if self.allowed is None else self.inputs[self.allowed].name

    def offer(self, index, now):
        """A message arrives on input ``index`` at ``now``: returns (forward it?, newly active name or None)."""
        self._last[index] = now
        holder = self.allowed
        if holder is None or holder == index or self.inputs[index].priority > self.inputs[holder].priority:
            self.allowed = index
            return True, (self.inputs[index].name if holder != index else None)
        return False, None

    def expire(self, now):
        """Apply the timeouts at ``now``: returns 'idle' if the holder lost the output, else None."""
        if self.allowed is None:
            return None
        if now < self._last[self.allowed]:     # the clock moved back: the timeout runs from now
            self._last[self.allowed] = now
        if now - self._last[self.allowed] > self.inputs[self.allowed].timeout:
            self.allowed = None
            return IDLE
        return None

"""The sampling publisher's record of its samples (what a landmark needs, seven doubles
each), from which a recorder restarted mid-recording rebuilds the landmarks it missed;
past ``capacity`` the oldest half goes (docs/recording.md, "File")."""
import math
from array import array
from collections import namedtuple

#: PathSample.command values: a tick, the last; ``START``: a RecordedSamples answer's entry 0.
SAMPLE, FINAL, START = 'sample', 'final', 'start'
COMMANDS = (SAMPLE, FINAL)
#: Samples kept by default (about 28 hours at one a second; 50 bytes each).
CAPACITY = 100000

#: One sample as published (``seq`` from 0 = the start), the odometry read at its stamp.
LoggedSample = namedtuple('LoggedSample', 'seq command stamp yaw period x y v w')
_FIELDS = LoggedSample._fields[2:]


class Ticks(object):
    """core/recorder.PathRecorder where the landmarks are made elsewhere: a take is the tick itself."""
    total_distance = 0.0

    def start(self, state):
        """The d chain is the saver's."""

    restart = start

    @staticmethod
    def take(state, yaw, period):
        return state, yaw, period


class SampleLog(object):
    """Samples of one recording, numbered from 0 (its start); see the module docstring."""

    def __init__(self, recording, start, capacity=CAPACITY):
        """``recording``: its id (start time, s); ``start``: the OdomState-like entry 0."""
        if not capacity >= 2:
            raise ValueError('sample log capacity must be >= 2, got %r' % (capacity,))
        self.recording = float(recording)
        self.capacity = int(capacity)
        self.first = 0              # seq of the oldest entry kept
        self.confirmed = {}         # recorder (its file) -> seq of the last sample it holds
        self._commands = [START]
        self._values = {name: array('d') for name in _FIELDS}
        self._add(start.stamp, start.yaw, 0.0, start)

    @property
    def last(self):
        """The seq of the newest sample (0: none since the start)."""
        return self.first + len(self._commands) - 1

    def append(self, command, stamp, yaw, period, odom):
        """Log the next sample (``odom``: OdomState-like at ``stamp``); return its seq."""
        if len(self._commands) >= self.capacity:
            self._drop(len(self._commands) // 2)
        self._commands.append(command)
        self._add(stamp, yaw, period, odom)
        return self.last

    def confirm(self, recorder, seq):
        """Recorder ``recorder`` holds the samples up to ``seq``; drops those no recorder needs."""
        if seq > self.last or seq < self.confirmed.get(recorder, 0):
            return                  # not taken yet, or older than what it said before
        self.confirmed[recorder] = seq
        self._drop(min(self.confirmed.values()) - self.first)

    def _drop(self, count):
        if count <= 0:
            return
        del self._commands[:count]
        for values in self._values.values():
            del values[:count]
        self.first += count

    def _add(self, stamp, yaw, period, odom):
        for name, value in zip(_FIELDS, (stamp, yaw, period, odom.x, odom.y, odom.v, odom.w)):
            self._values[name].append(value)

    def since(self, after):
        """Sample ``after`` and every later one (LoggedSample), None if ``after`` is not kept."""
        if not self.first <= after <= self.last:
            return None
        offset = after - self.first
        values = [self._values[name][offset:] for name in _FIELDS]
        return [LoggedSample(after + i, command, *row)
                for i, (command, row) in enumerate(zip(self._commands[offset:], zip(*values)))]


def answer_problem(answer, mark):
    """Why the RecordedSamples ``answer`` cannot continue a file last at SampleMark ``mark``, or ''."""
    if not answer.samples:
        return answer.message or 'no samples sent'
    after = mark.seq if mark else 0
    if mark is not None and answer.recording != mark.recording:
        return 'the answer is of recording %r, the file follows %r' % (answer.recording, mark.recording)
    columns = (answer.x, answer.y, answer.v, answer.w)
    if any(len(column) != len(answer.samples) for column in columns):
        return 'the answer has %d samples but odometry columns of %s' % (
            len(answer.samples), [len(column) for column in columns])
    seqs = [sample.seq for sample in answer.samples]
    if seqs != list(range(after, after + len(seqs))):
        return 'the samples are not %d, %d, ... in order (got %s...)' % (after, after + 1, seqs[:5])
    numbers = [sample.yaw for sample in answer.samples] + [sample.period for sample in answer.samples]
    if not all(math.isfinite(value) for column in columns + (numbers,) for value in column):
        return 'the answer holds a value that is not a finite number'
    return ''

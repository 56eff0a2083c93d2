"""The odometry feed's batches: messages taken several at a time, invisibly to readers.

:class:`Batches` takes the received messages ``size`` at a time on the receive thread;
a reader of the newest state first calls :meth:`Batches.catch_up`, which waits at most
one message (docs/cost.md, "The batched feed").
"""
import threading

#: Longest wait (s, wall) of :meth:`Batches.catch_up` for the next message; without
#: one (odometry stopped) the reader goes on with the states taken, and readers do not
#: wait again until a message arrives.
CATCH_UP_WAIT = 0.2


class Batches(object):
    """The messages received and not yet taken by ``take(buff)``, for a feed whose
    lock is ``lock`` (a threading.Condition, notified when messages are taken)."""

    def __init__(self, lock, take):
        self.lock = lock
        self.size = 1               # messages taken together
        self.taking = threading.Lock()   # one thread takes messages at a time, in order
        self.arrived = 0            # messages received
        self.waiting = 0            # threads in wait_until (catch_up, state_at(wait=))
        self._take = take
        self._pending = []          # raw messages received, not yet taken
        self._taken = 0             # messages taken (accepted or refused)
        self._stalled = None        # arrived when a catch_up gave up (no wait until more arrive)
        self._taker = None          # the thread taking messages (its listeners never wait)

    @property
    def pending(self):
        return len(self._pending)

    def receive(self, buff):
        """(receive thread) Queue ``buff``; take the queue once it is full or anyone waits."""
        with self.taking:
            self._pending.append(buff)
            self.arrived += 1
            if len(self._pending) < self.size and not self.waiting:
                return
            pending, self._pending = self._pending, []
            self._taker = threading.get_ident()
            try:
                for each in pending:
                    self._take(each)
            finally:
                self._taker = None
                with self.lock:
                    self._taken += len(pending)
                    if self.waiting:
                        self.lock.notify_all()

    def catch_up(self, timeout=CATCH_UP_WAIT):
        """Wait at most ``timeout`` wall seconds until the messages received so far are
        taken; True if they are. No wait with nothing pending, on the thread taking
        messages, or after a wait gave up, until another message arrives."""
        arrived = self.arrived
        if not self._pending or self._stalled == arrived:
            return True
        if threading.get_ident() == self._taker:
            return False
        taken = self.wait_until(lambda: self._taken >= arrived, timeout)
        if not taken:
            self._stalled = arrived
        return taken

    def wait_until(self, condition, timeout):
        """Wait at most ``timeout`` wall seconds until ``condition()`` (checked with the
        lock held) is true; True if it is. While anyone waits, every message is taken as
        it arrives, with those pending before it."""
        with self.lock:
            self.waiting += 1
            try:
                return self.lock.wait_for(condition, timeout=timeout)
            finally:
                self.waiting -= 1

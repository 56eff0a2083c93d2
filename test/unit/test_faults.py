"""ros/faults.py, without a master: a guarded callback or thread target that
raises declares the role and the exception (type and message) in the process's
fault registry (faults.declare: the listeners are the velocity outputs, zero
for good, and the mission's owner), turns the diagnostics to ERROR and logs the
traceback once; an exception while the node shuts down is not a failure."""
import logging
import threading

import pytest

rospy = pytest.importorskip('rospy')

from blind_navigation.core import outcome  # noqa: E402
from blind_navigation.ros import diagnostics, faults  # noqa: E402
from blind_navigation.ros.motion import MotionOutput  # noqa: E402


@pytest.fixture(autouse=True)
def registry(monkeypatch):
    """A fresh process fault registry (ros/faults.py)."""
    monkeypatch.setattr(faults, '_faults', {})
    monkeypatch.setattr(faults, '_listeners', [])
    monkeypatch.setattr(faults, '_codes', {})


class FakeDiagnostics(object):
    def __init__(self):
        self.checks, self.nows = {}, 0

    def add(self, name, check):
        self.checks[name] = check

    def now(self):
        self.nows += 1


class Stat(object):
    def __init__(self):
        self.level = self.message = None
        self.values = {}

    def summary(self, level, message):
        self.level, self.message = level, message

    def add(self, key, value):
        self.values[key] = value


class Rig(object):
    def __init__(self):
        self.diagnostics = FakeDiagnostics()
        self.reported = []          # what the registry's listeners (outputs, owner) hear
        self.faults = faults.Faults(self.diagnostics)
        faults.on_fault(self.reported.append)

    def status(self):
        stat = Stat()
        self.diagnostics.checks['role failures'](stat)
        return stat


def pruning():
    raise TypeError("'key' is an invalid keyword argument for bisect_left()")


REASON = "back_travel_client failed: TypeError: 'key' is an invalid keyword argument for bisect_left()"


def test_a_failing_callback_halts_reports_and_diagnoses():
    rig = Rig()
    assert rig.status().level == diagnostics.OK
    assert rig.faults.guard('back_travel_client')(pruning)() is None
    assert rig.reported == [REASON] and faults.faulty()
    assert rig.diagnostics.nows == 1
    stat = rig.status()
    assert (stat.level, stat.message, stat.values['failures']) == (diagnostics.ERROR, REASON, 1)


def test_a_guarded_callback_passes_arguments_and_result_through():
    rig = Rig()
    add = rig.faults.guard('rotate_pi')(lambda a, b=0: a + b)
    assert add(2, b=3) == 5
    assert rig.reported == [] and not faults.faulty()


def test_a_dying_thread_is_reported_not_silent(caplog):
    rig = Rig()
    thread = threading.Thread(target=rig.faults.guard('back_travel_server')(pruning))
    with caplog.at_level(logging.DEBUG):
        thread.start()
        thread.join(10.0)
    assert not thread.is_alive(), 'the guarded thread did not end'
    assert rig.reported == [REASON.replace('back_travel_client', 'back_travel_server')]
    fatal = [r.getMessage() for r in caplog.records if r.levelno >= logging.CRITICAL]
    assert len(fatal) == 1, fatal
    assert 'Traceback' in fatal[0] and 'in pruning' in fatal[0] and 'TypeError' in fatal[0]


def test_a_repeating_failure_reports_once_per_place(caplog):
    rig = Rig()
    guarded = rig.faults.guard('vision_monitor')(pruning)
    with caplog.at_level(logging.DEBUG):
        for _ in range(3):
            guarded()
    assert len(rig.reported) == rig.diagnostics.nows == 1
    assert len([r for r in caplog.records if 'Traceback' in r.getMessage()]) == 1
    stat = rig.status()
    assert (stat.message, stat.values['failures'], stat.values['repeats']) == (
        REASON.replace('back_travel_client', 'vision_monitor'), 1, 2)


def test_failures_at_two_places_are_both_reported():
    rig = Rig()
    rig.faults.guard('vision_monitor')(pruning)()
    rig.faults.guard('rotate_pi')(pruning)()
    assert [reason.split()[0] for reason in rig.reported] == ['vision_monitor', 'rotate_pi']
    assert '(and 1 more)' in rig.status().message


def test_a_failing_diagnostics_check_does_not_recurse():
    """A check that raises, guarded, fails while fail() publishes the diagnostics."""
    rig = Rig()
    check = rig.faults.guard('diagnostics')(pruning)
    rig.diagnostics.now = check         # what Diagnostics.now does: run every (guarded) check
    check()
    assert len(rig.reported) == 1 and rig.faults.repeats == 1


def test_a_failing_listener_does_not_stop_the_report():
    faults.on_fault(lambda reason: 1 / 0)
    rig = Rig()
    rig.faults.guard('rotate_pi')(pruning)()
    assert len(rig.reported) == 1


def test_an_exception_at_shutdown_is_not_a_failure(monkeypatch):
    rig = Rig()
    monkeypatch.setattr(faults, 'shutting_down', lambda: True)
    assert rig.faults.guard('rotate_pi')(pruning)() is None
    assert rig.reported == [] and not faults.faulty()


def test_system_exit_is_not_caught():
    rig = Rig()

    def leave():
        raise SystemExit(1)
    with pytest.raises(SystemExit):
        rig.faults.guard('rotate_pi')(leave)()
    assert rig.reported == []


def test_a_role_failure_stops_every_output_for_good():
    # the calibration's role may move without a mission: only the fault can stop it here
    outputs = [MotionOutput('calibrate_gyro', 0.2, 1.0), MotionOutput('calibrate_gyro', 0.2, 1.0)]
    sent = []
    for output in outputs:
        output._send = lambda v, w, sent=sent: sent.append((v, w))
        output.publish(0.1, 0.5)
    assert sent == [(0.1, 0.5), (0.1, 0.5)]
    del sent[:]
    Rig().faults.guard('rotate_pi')(pruning)()
    assert sent == [(0.0, 0.0), (0.0, 0.0)]      # at once, from the registry's listeners
    for output in outputs:
        output.release()                # a new turn or goal would release: not after a failure
        output.publish(0.1, 0.5)
    assert set(sent) == {(0.0, 0.0)} and len(sent) == 4


def test_a_fault_carries_its_outcome_code_to_the_owner():
    """The owner ends the mission with the code the fault was declared with (ros/faults.code_of):
    a role's exception ROLE_FAILURE, a refused topic WIRING; another process's report (a text
    this process never declared) ROLE_FAILURE."""
    rig = Rig()
    rig.faults.guard('rotate_pi')(pruning)()
    faults.refuse('/odom', 'nav_msgs/Odometry', 'std_msgs/String')
    failed, refused = rig.reported
    assert refused.startswith('wrong wiring: /odom carries std_msgs/String')
    assert (faults.code_of(failed), faults.code_of(refused)) == (outcome.ROLE_FAILURE, outcome.WIRING)
    assert faults.code_of('rotate_pi failed: OSError: gone (/rotate_pi)') == outcome.ROLE_FAILURE

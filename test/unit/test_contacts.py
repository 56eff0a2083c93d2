"""core/pause.Contacts as a bounded contact (issue 28 item 5): a bumper's bounces are
one contact, and contact_timeout bounds it from its first press. The bumper is fed
as the drive loop feeds it: each control cycle, whether it is pressed now or was
since the last cycle, and how many presses came since."""
import types

import pytest

from blind_navigation.core.pause import CONTACT_DEFAULTS, PAUSE, Contacts
from blind_navigation.core.safety import SafetyEvents

#: s: the back travel server's control cycle (control_rate 50 Hz).
CYCLE = 0.02
#: s from a press to the cycle that sees it (drive's offset): the contact's clock starts there.
SEEN = 0.007
#: s: a 10 Hz chatter, pressed half of each period.
CHATTER, PRESSED = 0.1, 0.05
SENSOR = 'bumper center pressed'


def contacts(**changes):
    return Contacts(types.SimpleNamespace(**dict(CONTACT_DEFAULTS, **changes)))


def chatter(start, until):
    """(press, release) times of a 10 Hz chatter from ``start`` to ``until``."""
    count = int(round((until - start) / CHATTER))
    return [(start + k * CHATTER, start + k * CHATTER + PRESSED) for k in range(count)]


def drive(c, presses, end, offset=SEEN):
    """Feed ``c`` a bumper pressed over ``presses`` ((press, release) times) each CYCLE
    from ``offset`` to ``end``; [(time, decision)] until the first abort reason."""
    decisions, last, now = [], -1.0, offset
    while now <= end:
        new = sum(1 for pressed, _ in presses if last < pressed <= now)
        held = any(pressed <= now < released for pressed, released in presses)
        decision = c.decide(bool(new or held), now, new, [SENSOR] if new or held else [])
        decisions.append((now, decision))
        if decision not in (None, PAUSE):
            break
        last, now = now, round(now + CYCLE, 9)
    return decisions


def abort_of(decisions):
    now, decision = decisions[-1]
    assert decision not in (None, PAUSE), 'no abort by %.2f s' % now
    return now, decision


def test_a_10_hz_chatter_is_one_contact_and_aborts_at_contact_timeout_from_its_first_press():
    c = contacts(contact_timeout=10.0, contact_wait=2.0)
    first = 3.0
    decisions = drive(c, chatter(first, first + 40.0), 50.0)
    at, reason = abort_of(decisions)
    assert first + SEEN + 10.0 < at <= first + SEEN + 10.0 + CYCLE + 1e-9
    assert all(d == PAUSE for t, d in decisions[:-1] if t >= first), 'the robot drove during the contact'
    assert c.count == 1 and c.sensors == [SENSOR]
    assert reason.startswith('bumper contact 1 lasted 10.0 s from its first press (101 presses')
    assert reason.endswith('longer than contact_timeout 10.0 s')


def test_a_chatter_counted_by_cycles_aborts_the_same():
    c = contacts(contact_timeout=10.0)
    first = 0.5
    for now in [first + CYCLE * k for k in range(600)]:
        phase = (now - first) % CHATTER
        decision = c.decide(phase < PRESSED, now)  # presses=None: counted on the cycles
        if decision not in (None, PAUSE):
            break
    assert first + 10.0 < now <= first + 10.0 + CYCLE + 1e-9
    assert 'from its first press (101 presses' in decision


def test_a_stuck_press_aborts_at_contact_timeout():
    c = contacts(contact_timeout=10.0)
    at, reason = abort_of(drive(c, [(1.0, 100.0)], 30.0))
    assert 11.0 + SEEN < at <= 11.0 + SEEN + CYCLE + 1e-9
    assert reason == 'bumper contact 1 pressed for 10.0 s, longer than contact_timeout 10.0 s'


def test_a_chatter_that_stops_before_contact_timeout_resumes_after_contact_wait():
    c = contacts(contact_timeout=10.0, contact_wait=2.0)
    decisions = drive(c, chatter(1.0, 9.0), 15.0)
    assert [t for t, d in decisions if d == PAUSE][-1] == pytest.approx(8.95 + 2.0, abs=CYCLE)
    assert decisions[-1][1] is None and c.count == 1 and c.first is None


def test_a_press_released_before_contact_timeout_is_not_timed_during_its_wait():
    c = contacts(contact_timeout=10.0, contact_wait=2.0)
    decisions = drive(c, [(1.0, 10.5)], 20.0)     # 9.5 s pressed, then 2 s of wait: 11.5 s
    assert all(d in (None, PAUSE) for _, d in decisions)
    assert decisions[-1][1] is None


def test_presses_further_apart_than_contact_wait_are_separate_contacts_up_to_max_contacts():
    c = contacts(max_contacts=3, contact_wait=2.0)
    presses = [(start, start + 0.5) for start in (1.0, 4.0, 7.0, 10.0)]   # released 2.5 s apart
    at, reason = abort_of(drive(c, presses, 20.0))
    assert 10.0 <= at <= 10.0 + CYCLE
    assert reason == 'bumper contact 4 of at most 3 (max_contacts)'


def test_presses_closer_than_contact_wait_are_one_contact():
    c = contacts(max_contacts=1, contact_wait=2.0)
    presses = [(start, start + 0.5) for start in (1.0, 3.0, 5.0)]         # released 1.5 s apart
    decisions = drive(c, presses, 10.0)
    assert decisions[-1][1] is None and c.count == 1 and c.presses == 3


def test_the_contact_names_every_bumper_it_pressed():
    c = contacts()
    c.decide(True, 0.0, 1, ['bumper left pressed'])
    c.decide(False, 0.1, 0, [])
    c.decide(True, 0.2, 1, ['bumper center pressed', 'bumper left pressed', 'bumper center pressed'])
    assert c.sensors == ['bumper left pressed', 'bumper center pressed'] and c.presses == 2


def test_a_bumper_press_continues_a_contact_within_the_window_of_a_release():
    events = SafetyEvents()
    assert not events.continues('bumper', 0.0, 2.0)
    events.update('bumper', 1, 1, 0.0)
    assert events.continues('bumper', 0.05, 2.0)        # another bumper while one is pressed
    events.update('bumper', 1, 0, 0.05)
    assert events.continues('bumper', 1.9, 2.0)         # a bounce
    assert not events.continues('bumper', 2.1, 2.0)     # a new contact
    assert not events.continues('bumper', 0.0, 2.0)     # the clock went back: a new one
    assert not events.continues('cliff', 1.0, 2.0)      # other kinds are their own

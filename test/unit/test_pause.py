"""core/pause.py: bumper contacts and an operator's takeover, on made-up times."""
import types

import pytest

from blind_navigation.core.pause import (CONTACT_DEFAULTS, PAUSE, TAKEOVER_DEFAULTS, Contacts,
                                         Takeover)
from blind_navigation.core.safety import SafetyEvents, is_contact


def contacts(**changes):
    return Contacts(types.SimpleNamespace(**dict(CONTACT_DEFAULTS, **changes)))


def takeover(**changes):
    return Takeover(types.SimpleNamespace(**dict(TAKEOVER_DEFAULTS, **changes)))


def test_a_press_holds_until_contact_wait_after_the_release():
    c = contacts(contact_wait=2.0)
    assert c.decide(False, 0.0) is None
    assert c.decide(True, 1.0) == PAUSE
    assert c.decide(True, 1.5) == PAUSE
    assert c.decide(False, 2.0) == PAUSE        # released at 2.0: wait until 4.0
    assert c.decide(False, 3.9) == PAUSE
    assert c.decide(False, 4.0) is None
    assert c.count == 1 and c.first is None


def test_a_press_during_the_wait_is_the_same_contact_and_restarts_the_wait():
    c = contacts(contact_wait=2.0)
    c.decide(True, 0.0)
    c.decide(False, 1.0)
    assert c.decide(True, 2.0) == PAUSE
    assert c.decide(False, 2.5) == PAUSE
    assert c.decide(False, 4.4) == PAUSE
    assert c.decide(False, 4.5) is None
    assert c.count == 1


def test_the_contact_after_max_contacts_aborts_naming_the_count():
    c = contacts(max_contacts=2, contact_wait=0.0)
    for start in (0.0, 10.0):
        assert c.decide(True, start) == PAUSE
        assert c.decide(False, start + 1) is None
    reason = c.decide(True, 20.0)
    assert reason == 'bumper contact 3 of at most 2 (max_contacts)'


def test_max_contacts_zero_aborts_at_the_first_contact():
    assert 'contact 1 of at most 0' in contacts(max_contacts=0).decide(True, 0.0)


def test_a_press_longer_than_contact_timeout_aborts():
    c = contacts(contact_timeout=10.0)
    assert c.decide(True, 0.0) == PAUSE
    assert c.decide(True, 10.0) == PAUSE
    reason = c.decide(True, 10.1)
    assert 'pressed for 10.1 s, longer than contact_timeout 10.0 s' in reason


def test_contact_params_are_checked():
    with pytest.raises(ValueError):
        contacts(contact_timeout=0.0)
    with pytest.raises(ValueError):
        contacts(contact_wait=-1.0)
    with pytest.raises(ValueError):
        contacts(max_contacts=-1)


def test_only_the_bumper_is_a_contact():
    events = SafetyEvents()
    events.update('bumper', 1, 1)
    events.update('cliff', 0, 1)
    assert events.terminal == ['cliff left cliff']
    assert is_contact('bumper center pressed') and not is_contact('wheel drop left dropped')


def test_a_foreign_command_takes_over_until_takeover_wait_of_silence():
    t = takeover(takeover_wait=2.0)
    assert t.active(0.0) is None
    t.command('/joystick', 1.0)
    assert t.active(1.0) == 'operator takeover by /joystick'
    t.command('/joystick', 3.0)
    assert t.active(4.9) is not None
    assert t.active(5.0) is None
    assert t.paused(5.0) == pytest.approx(4.0)


def test_a_higher_mux_input_takes_over_while_active_then_takeover_wait():
    t = takeover(takeover_wait=1.0)
    t.mux_active('Teleoperation', 0.0)          # the layer's own input: no takeover
    assert t.active(0.0) is None
    t.mux_active('Safe reactive controller', 1.0)
    assert 'cmd_vel_mux input Safe reactive controller' in t.active(1.0)
    assert t.active(50.0) is not None           # active as long as the mux says so
    t.mux_active('idle', 60.0)
    assert t.active(60.5) is not None
    assert t.active(61.0) is None


def test_takeover_params_are_checked():
    with pytest.raises(ValueError):
        takeover(on_takeover='fight')
    with pytest.raises(ValueError):
        takeover(takeover_wait=0.0)


def _driving(watch, until, step=0.02):
    """The layer sends (0.2, 0.1) every ``step`` s up to ``until`` and the mux echoes each."""
    t = 0.0
    while t < until:
        watch.sent(0.2, 0.1, t)
        watch.at_base(0.2, 0.1, t + 0.005, '/mobile_base/commands/velocity')
        t += step
    return t


def test_an_operators_command_at_the_base_takes_over_before_the_layer_hears_it():
    # the layer's own subscription has not connected to the new publisher: only the base shows it
    watch = takeover()
    t = _driving(watch, 1.0)
    assert watch.active(t) is None
    watch.at_base(0.05, 0.0, t + 0.01, '/mobile_base/commands/velocity')
    assert 'did not send' in watch.active(t + 0.02)
    assert watch.active(t + 0.01 + TAKEOVER_DEFAULTS['takeover_wait'] + 0.01) is None


def test_the_base_echoing_the_layer_or_zero_or_a_stranger_while_standing_is_no_takeover():
    watch = takeover()
    t = _driving(watch, 1.0)
    watch.at_base(0.0, 0.0, t, 'out')              # someone's zero cannot fight the layer
    assert watch.active(t) is None
    standing = takeover()
    standing.sent(0.0, 0.0, 0.0)
    standing.at_base(0.0, 0.0, 0.001, 'out')
    standing.at_base(0.3, 0.0, 0.01, 'out')        # the layer does not drive: not its business
    assert standing.active(0.02) is None


def test_a_base_that_never_echoes_the_layer_is_no_takeover():
    # a velocity smoother between the mux and the base changes every command
    watch = takeover()
    for i in range(100):
        watch.sent(0.2, 0.1, i * 0.02)
        watch.at_base(0.19, 0.09, i * 0.02 + 0.005, 'out')
    assert watch.active(2.0) is None

"""The outcome codes (core/outcome.py) are MissionStatus's OUTCOME_* constants, one per
cause, documented in docs/safety.md and the README (issue 31, item 3)."""
import os
import re

from blind_navigation.core import drive, outcome

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
CONSTANT = re.compile(r'^\s*uint16\s+OUTCOME_([A-Z_]+)\s*=\s*(\d+)', re.M)


def read(relative):
    with open(os.path.join(REPO, relative)) as text:
        return text.read()


def msg_constants():
    return {int(number): name for name, number in CONSTANT.findall(read('msg/MissionStatus.msg'))}


def test_the_message_constants_are_the_cores():
    assert msg_constants() == dict(outcome.NAMES)


def test_one_number_per_name_and_none_is_zero():
    assert len(set(outcome.NAMES.values())) == len(outcome.NAMES)
    assert outcome.NAMES[0] == 'NONE' and outcome.NONE == 0


def test_the_status_field_follows_the_old_fields():
    fields = [line.split()[1] for line in read('msg/MissionStatus.msg').splitlines()
              if line.strip() and not line.lstrip().startswith('#') and '=' not in line]
    assert fields == ['header', 'state', 'reason', 'warnings', 'landmarks', 'completed', 'outcome']


def test_every_code_is_documented():
    safety, readme = read('docs/safety.md'), read('README.md')
    for code, name in outcome.NAMES.items():
        assert re.search(r'\| %d \| `%s` \|' % (code, name), safety), (code, name)
        assert '%d `%s`' % (code, name) in readme or name == 'NONE', (code, name)


def test_the_log_line_names_the_code():
    assert outcome.phrase(outcome.CANCELLED, 'cancelled by request') == \
        'cancelled by request [outcome CANCELLED (20)]'
    assert outcome.phrase(outcome.NONE, 'vision lost') == 'vision lost'
    assert outcome.describe(99) == 'UNKNOWN (99)'


def test_a_drive_outcome_carries_its_cause():
    assert drive.Outcome(drive.TIMED_OUT, 'late').cause == outcome.TIMEOUT
    assert drive.Outcome(drive.SAFETY_STOP, 'bumper', outcome.CONTACTS).cause == outcome.CONTACTS
    assert drive.Outcome(drive.SUCCEEDED, '').cause == outcome.NONE
    assert set(drive.KIND_CODES) == {drive.SUCCEEDED, drive.CANCELLED, drive.FAILED, drive.TIMED_OUT,
                                     drive.SAFETY_STOP, drive.ODOMETRY_LOST, drive.PREEMPTED,
                                     drive.TAKEN_OVER}


def test_a_takeover_with_on_takeover_abort_and_a_bumper_in_the_turn_carry_their_codes():
    """Played by the harness on core/mission.Mission (test_mission_harness's mission)."""
    from test_mission_harness import _play
    from test_mission_harness_limits import _params
    taken = _play(('takeover', 'return', 5.0, 1.0, (0.0, 0.0)), params=_params(on_takeover='abort'))
    assert (taken.result.status, taken.mission.machine.outcome) == ('aborted', outcome.TAKEOVER), \
        taken.result.reason
    assert 'on_takeover abort' in taken.result.reason
    bumped = _play(('bumper', 'turn', 1.0, 0.5), heading_correction=False)     # the turn at once
    assert (bumped.result.status, bumped.mission.machine.outcome) == ('aborted', outcome.CONTACTS), \
        bumped.result.reason
    assert 'the pi turn: safety stop: bumper' in bumped.result.reason

"""core/params.py: a schema validates a role's params once into a frozen, typed
object, and a bad value is an error naming role, param, value and range."""
import pytest

from blind_navigation.core.params import REQUIRED, Param, ParamError, Schema
from blind_navigation.core.role_params import BACK_TRAVEL_SERVER, SCHEMAS

SCHEMA = Schema('probe', (
    Param('rate', 2.0, 'Hz', 'a rate', lo=0.1, hi=10.0),
    Param('count', 3, '', 'a count', lo=0, hi=5),
    Param('mode', REQUIRED, '', 'a mode', choices=('a', 'b')),
    Param('flag', True, '', 'a flag'),
), fixed={'margin': 1.5, 'rate': 99.0}, shared=('rate', 'other'))


def test_validate_types_defaults_and_freezes():
    p = SCHEMA.validate({'rate': 4, 'mode': 'b'})
    assert (p.rate, p.count, p.mode, p.flag, p.margin) == (4.0, 3, 'b', True, 1.5)
    assert type(p.rate) is float
    with pytest.raises(AttributeError):
        p.rate = 1.0
    assert SCHEMA.shared == ('rate',) and 'rate' not in SCHEMA.fixed


@pytest.mark.parametrize('values, words', [
    ({'mode': 'a', 'rate': 20.0}, ["probe", "~x/rate = 20.0", "[0.1, 10.0] Hz"]),
    ({'mode': 'a', 'rate': True}, ['rate = True', 'a number']),
    ({'mode': 'a', 'rate': float('nan')}, ['rate = nan']),
    ({'mode': 'a', 'count': 2.0}, ['count = 2.0', 'an integer in [0, 5]']),
    ({'mode': 'c'}, ["mode = 'c'", 'one of a, b']),
    ({'mode': 'a', 'flag': 'yes'}, ["flag = 'yes'", 'true or false']),
    ({}, ['~x/mode not set']),
    ({'mode': 'a', 'margin': 2.0}, ['unknown param ~x/margin']),
])
def test_a_bad_value_names_role_param_value_and_range(values, words):
    with pytest.raises(ParamError) as error:
        SCHEMA.validate(values, '~x/')
    for word in words:
        assert word in str(error.value)


def test_make_overrides_constants_for_tests_but_still_checks_user_params():
    p = SCHEMA.make(mode='a', margin=0.5, count=5)
    assert (p.margin, p.count) == (0.5, 5)
    with pytest.raises(ParamError):
        SCHEMA.make(mode='a', count=6)


def test_every_schema_accepts_its_own_defaults():
    for schema in SCHEMAS:
        required = {p.name: (p.choices[0] if p.choices else True)
                    for p in schema.params if p.default is REQUIRED}
        params = schema.validate(required)
        for param in schema.params:
            assert getattr(params, param.name) == required.get(param.name, param.default)
    assert BACK_TRAVEL_SERVER.make(control='time').control_rate == 50.0


def test_a_list_param_takes_distinct_choices():
    schema = Schema('probe', (Param('detectors', ('a', 'b'), '', 'which', choices=('a', 'b', 'c')),))
    assert schema.validate({'detectors': ['c', 'a']}).detectors == ('c', 'a')
    assert schema.validate({}).detectors == ('a', 'b') and schema.validate({'detectors': []}).detectors == ()
    for bad in (['a', 'd'], ['a', 'a'], 'a', [1]):
        with pytest.raises(ParamError) as error:
            schema.validate({'detectors': bad})
        assert 'a list of a, b, c' in str(error.value)

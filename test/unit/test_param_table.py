"""scripts/param_table.py: docs/params.md and README's params block match the
code's DEFAULTS (its --check, in-process: it reads the role modules as text, so
neither rospy nor the built messages are needed), and a param without a
meaning is named with where it is written."""
import importlib.util
import os

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
SPEC = importlib.util.spec_from_file_location('param_table', os.path.join(REPO, 'scripts', 'param_table.py'))
param_table = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(param_table)

PROBE = '''
from blind_navigation.core.rotation import ROTATION_DEFAULTS
from blind_navigation.ros.common import REQUIRED


class Probe(object):
    DEFAULTS = dict(ROTATION_DEFAULTS,
                    control_rate=50.0,     # Hz of the probe's loop
                                           # (a second comment line)
                    mode=REQUIRED,
                    max_w=ROTATION_DEFAULTS['max_w'])
'''


@pytest.fixture
def probe(monkeypatch):
    """A role module ``blind_navigation.ros.probe`` (text only) listed as the one role."""
    path = os.path.join(REPO, 'blind_navigation', 'ros', 'probe.py')
    monkeypatch.setitem(param_table._SOURCES, 'blind_navigation.ros.probe',
                        param_table.Source(PROBE, 'blind_navigation.ros.probe', path))
    monkeypatch.setattr(param_table, 'ROLES', [('probe', 'probe', 'Probe')])
    return param_table.source('blind_navigation.ros.probe')


def test_docs_params_and_the_readme_block_are_generated_from_the_code():
    stale = [os.path.relpath(path, REPO) for path, _ in param_table.stale()]
    assert not stale, '%s out of date: run /usr/bin/python3 scripts/param_table.py' % ', '.join(stale)


def test_every_role_param_is_in_docs_params_with_its_default():
    with open(os.path.join(REPO, 'docs', 'params.md')) as stream:
        text = stream.read()
    for role, param, default, meaning in param_table.rows():
        assert '| `%s` | %s | %s |' % (param, param_table.value(default), meaning.replace('|', '\\|')) \
            in text, (role, param)


def test_a_meaning_is_the_comment_on_the_line_or_where_the_value_comes_from(probe):
    expression = probe.defaults('DEFAULTS', 'Probe')
    assert param_table.meaning(probe, expression, 'control_rate')[0] == \
        "Hz of the probe's loop (a second comment line)"
    rotation = param_table.source('blind_navigation.core.rotation')
    core_max_w = rotation.comment(param_table.own_keys(rotation.defaults('ROTATION_DEFAULTS'))['max_w'][0])
    assert core_max_w.startswith('rad/s')
    assert param_table.meaning(probe, expression, 'max_w')[0] == core_max_w       # X_DEFAULTS['max_w']
    assert param_table.meaning(probe, expression, 'tolerance')[0].startswith('rad')  # merged in
    defaults, _, _ = param_table.role_defaults('probe', 'Probe')
    assert defaults['mode'] is param_table.REQUIRED and defaults['control_rate'] == 50.0


def test_a_param_without_a_comment_is_named_with_its_line(probe):
    with pytest.raises(SystemExit) as failure:
        param_table.rows()
    message = str(failure.value)
    assert 'mode (probe, written at blind_navigation/ros/probe.py:10)' in message
    assert 'control_rate' not in message and 'max_w' not in message

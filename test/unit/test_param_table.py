"""scripts/param_table.py: docs/params.md and README's params block match the
roles' schemas (its --check, in-process: only core is imported), every role
reads its params through a schema listed there, and at most 40 params are
left for a user to set (issue 22)."""
import glob
import importlib.util
import os
import re

from blind_navigation.core import role_params

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
SPEC = importlib.util.spec_from_file_location('param_table', os.path.join(REPO, 'scripts', 'param_table.py'))
param_table = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(param_table)


def test_docs_params_and_the_readme_block_are_generated_from_the_schemas():
    stale = [os.path.relpath(path, REPO) for path, _ in param_table.stale()]
    assert not stale, '%s out of date: run /usr/bin/python3 scripts/param_table.py' % ', '.join(stale)


def test_every_user_param_is_in_docs_params_with_its_default_and_range():
    with open(os.path.join(REPO, 'docs', 'params.md')) as stream:
        text = stream.read()
    for param, roles in param_table.rows():
        assert '| `%s` | %s | %s | %s | %s |' % (param.name, ', '.join(roles), param.unit,
                                                param_table.allowed(param),
                                                param_table.value(param.default)) in text, param


def test_at_most_40_params_a_user_can_set():
    rows = [line for line in open(os.path.join(REPO, 'docs', 'params.md')) if line.startswith('| `')]
    assert len(rows) == len(param_table.rows()) <= 40, len(rows)


def test_every_role_reads_its_params_through_a_listed_schema():
    used = set()
    for path in glob.glob(os.path.join(REPO, 'blind_navigation', 'ros', '*.py')):
        with open(path) as stream:
            text = stream.read()
        assert not re.search(r'^\s+DEFAULTS = ', text, re.M), '%s: a role DEFAULTS dict (use a schema)' % path
        used.update(re.findall(r'^\s+SCHEMA = (\w+)$', text, re.M))
    assert used and {getattr(role_params, name) for name in used} == set(role_params.SCHEMAS)

"""A product module's docstring says what the module is for, in at most 8 lines
(docs/DESIGN.md, Conventions): the why lives in docs/."""
import ast
import os

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
PRODUCT = [os.path.join(REPO, 'blind_navigation', name) for name in ('__init__.py', 'names.py')] + sorted(
    os.path.join(root, name) for room in ('core', 'ros', 'nodes')
    for root, _, names in os.walk(os.path.join(REPO, 'blind_navigation', room))
    for name in names if name.endswith('.py'))
MAX_LINES = 8


def docstring_lines(path):
    """Source lines the module docstring spans, its quotes included (0: none)."""
    with open(path) as stream:
        tree = ast.parse(stream.read(), path)
    first = tree.body[0] if tree.body else None
    if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
            and isinstance(first.value.value, str)):
        return first.end_lineno - first.lineno + 1
    return 0


def test_the_product_is_found():
    assert len(PRODUCT) > 30, PRODUCT


@pytest.mark.parametrize('path', PRODUCT, ids=lambda p: os.path.relpath(p, REPO))
def test_a_module_docstring_is_short(path):
    lines = docstring_lines(path)
    assert lines <= MAX_LINES, (
        '%s: the module docstring spans %d lines (at most %d): keep what the module is '
        'for, move the why to docs/' % (os.path.relpath(path, REPO), lines, MAX_LINES))

"""The product's rooms stay small enough to hold in one's head (issue 22): no file
in core/, ros/, nodes/ or names.py over MAX_FILE_LINES lines, no class over
MAX_CLASS_LINES (docs/DESIGN.md); at most MAX_ROSTESTS rostest files."""
import ast
import os

import pytest

PACKAGE = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..', 'blind_navigation'))
PRODUCT = ('core', 'ros', 'nodes', 'names.py')
MAX_FILE_LINES = 400
MAX_CLASS_LINES = 250
#: Known offenders (none since issue 22's splits): a file or class listed here must
#: still offend, so that whoever brings it under its limit takes it off.
KNOWN_LONG_FILES = set()
KNOWN_LONG_CLASSES = set()


def product_files():
    found = []
    for part in PRODUCT:
        top = os.path.join(PACKAGE, part)
        if part.endswith('.py'):
            found.append(top)
            continue
        found += [os.path.join(root, name) for root, _, names in os.walk(top)
                  for name in names if name.endswith('.py')]
    return sorted(os.path.relpath(path, PACKAGE) for path in found)


def read(relative):
    with open(os.path.join(PACKAGE, relative)) as source:
        return source.read()


def long_classes(relative):
    """'file:Class' -> lines, of the classes over MAX_CLASS_LINES in ``relative``."""
    tree = ast.parse(read(relative))
    return {'%s:%s' % (relative, node.name): node.end_lineno - node.lineno + 1
            for node in ast.walk(tree) if isinstance(node, ast.ClassDef)
            and node.end_lineno - node.lineno + 1 > MAX_CLASS_LINES}


def test_the_product_is_found():
    assert {'core/store.py', 'ros/odometry.py', 'names.py'} <= set(product_files())


@pytest.mark.parametrize('relative', product_files())
def test_no_file_over_the_limit(relative):
    lines = len(read(relative).splitlines())
    if relative in KNOWN_LONG_FILES:
        return
    assert lines <= MAX_FILE_LINES, '%s has %d lines (at most %d: split it into rooms by job)' % (
        relative, lines, MAX_FILE_LINES)


@pytest.mark.parametrize('relative', product_files())
def test_no_class_over_the_limit(relative):
    found = {name: lines for name, lines in long_classes(relative).items()
             if name not in KNOWN_LONG_CLASSES}
    assert not found, 'classes over %d lines: %s' % (MAX_CLASS_LINES, found)


def test_the_known_offenders_still_offend():
    """A split that landed takes its file off the lists (or the list hides a regrowth)."""
    fixed = [name for name in KNOWN_LONG_FILES if len(read(name).splitlines()) <= MAX_FILE_LINES]
    fixed += [name for name in KNOWN_LONG_CLASSES
              if name not in long_classes(name.split(':')[0])]
    assert not fixed, 'under the limit now: remove from KNOWN_LONG_FILES/_CLASSES: %s' % fixed


#: Issue 30's budget: the product (core, ros, nodes, names.py) and ros/ alone, in lines.
MAX_PRODUCT_LINES, MAX_ROS_LINES = 8000, 3000


def lines_of(prefix=''):
    return sum(len(read(path).splitlines()) for path in product_files() if path.startswith(prefix))


def test_the_budget_counts_the_product():
    assert 1000 < lines_of('ros/') < lines_of()


@pytest.mark.xfail(strict=True, reason='issue 30 item 6 is open: the paper layout\'s roles in ros/ are '
                   'still apart from the mission object (docs/DESIGN.md); strict: remove this mark '
                   'once the budget is met')
def test_the_product_within_issue_30s_budget():
    assert lines_of() <= MAX_PRODUCT_LINES and lines_of('ros/') <= MAX_ROS_LINES, (
        'product %d lines (at most %d), ros/ %d (at most %d)'
        % (lines_of(), MAX_PRODUCT_LINES, lines_of('ros/'), MAX_ROS_LINES))


#: Issue 30 item 7: rostest files (each a roscore and launch of its own in `make test`).
MAX_ROSTESTS = 30


def test_at_most_max_rostests_test_files():
    found = sorted(name for name in os.listdir(os.path.join(PACKAGE, '..', 'test', 'rostest'))
                   if name.endswith('.test'))
    assert 0 < len(found) <= MAX_ROSTESTS, (
        '%d .test files in test/rostest (at most %d: share a launch, docs/testing.md): %s'
        % (len(found), MAX_ROSTESTS, found))

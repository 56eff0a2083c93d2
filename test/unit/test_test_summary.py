"""scripts/test_summary.py: the `N passed, N failed` line of make test counts
every failure, including a rosunit suite whose setUpClass raised (errors="1"
and no test case: counted as passed-by-silence before, as in a baseline run
where recording_fake_turtlebot's set-up gave up and the line said 0 of it)."""
import importlib.util
import os

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
SPEC = importlib.util.spec_from_file_location('test_summary', os.path.join(REPO, 'scripts', 'test_summary.py'))
test_summary = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(test_summary)

SET_UP_CLASS_ERROR = ('<?xml version="1.0" encoding="utf-8"?>\n<testsuite errors="1" failures="0" '
                      'name="unittest.suite.TestSuite" tests="0" time="45.5"><system-out/></testsuite>')
TWO_CASES = ('<testsuite errors="0" failures="1" name="s" tests="2"><testcase classname="c" name="a"/>'
             '<testcase classname="c" name="b"><failure message="off by one"/></testcase></testsuite>')
ROSTEST_ENTRY = ('<testsuite errors="0" failures="0" name="s" tests="1"><testcase classname="rostest.runner.RosTest"'
                 ' name="testx" time="49.0"/></testsuite>')


def summarise(tmp_path, files, capsys):
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    status = test_summary.main(str(tmp_path))
    return status, capsys.readouterr().out.splitlines()


def test_a_suite_error_outside_any_case_is_a_failure(tmp_path, capsys):
    status, lines = summarise(tmp_path, {'rosunit-x.xml': SET_UP_CLASS_ERROR, 'rostest-test_x.xml': ROSTEST_ENTRY,
                                         'pytest-unit.xml': TWO_CASES.replace('failures="1"', 'failures="0"')
                                         .replace('<failure message="off by one"/>', '')}, capsys)
    assert status == 1
    assert lines[-1] == '2 passed, 1 failed'
    assert lines[0].startswith('FAILED rosunit-x.xml') and 'outside its test cases' in lines[0]


def test_failures_of_cases_are_counted_once(tmp_path, capsys):
    status, lines = summarise(tmp_path, {'rosunit-y.xml': TWO_CASES}, capsys)
    assert status == 1
    assert lines == ['FAILED rosunit-y.xml c.b: off by one', '1 passed, 1 failed']


def test_a_case_with_a_failure_and_an_error_is_not_counted_again(tmp_path, capsys):
    both = ('<testsuite errors="1" failures="1" name="s" tests="1"><testcase classname="c" name="a">'
            '<failure message="assert"/><error message="teardown"/></testcase></testsuite>')
    status, lines = summarise(tmp_path, {'pytest-z.xml': both}, capsys)
    assert status == 1
    assert lines == ['FAILED pytest-z.xml c.a: assert', '0 passed, 1 failed']


def test_a_class_fixture_error_is_shown_with_its_message(tmp_path, capsys):
    """The shape rosunit writes when a setUpClass raised in a node that imports
    test/rostest/waiting.py: the error's line in system-err, escaped CDATA and all."""
    fixture_error = ('<testsuite errors="1" failures="0" name="unittest.suite.TestSuite" tests="1">'
                     '<testcase classname="__main__.TestY" name="test_b" time="0.0000" />'
                     '<system-out>&lt;![CDATA[\n\n]]&gt;</system-out><system-err>&lt;![CDATA[\n'
                     'CLASS FIXTURE ERROR setUpClass (__main__.TestX): AssertionError: gave up after 90 s\n'
                     'Traceback (most recent call last):\n  File "x.py", line 9, in setUpClass\n'
                     'AssertionError: gave up after 90 s\n\n]]&gt;</system-err></testsuite>')
    status, lines = summarise(tmp_path, {'rosunit-x.xml': fixture_error}, capsys)
    assert status == 1
    assert lines == ['FAILED rosunit-x.xml unittest.suite.TestSuite.(outside any test case): 1 error(s)/failure(s) '
                     'the suite counts outside its test cases (setUpClass or tearDownClass?): setUpClass '
                     '(__main__.TestX): AssertionError: gave up after 90 s', '1 passed, 1 failed']

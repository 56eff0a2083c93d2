"""The one polling wait of the rostest nodes: wall-clock bounded, so a stalled sim
clock fails the test with a message instead of hanging it. Imported, it also keeps a
class fixture's error message in its results."""
import sys
import time
import unittest.suite

import rospy


#: The start of the line naming a class fixture's error in a rosunit suite's system-err.
FIXTURE_ERROR = 'CLASS FIXTURE ERROR'


def keep_class_fixture_errors():
    """rosunit's xml result writes a test case only for a test it saw start: the error of
    a setUpClass or tearDownClass (unittest's _ErrorHolder) is counted in the suite's
    errors, but its message is lost. Print it to stderr, which rosunit keeps as the
    suite's system-err, a line starting with FIXTURE_ERROR and then the traceback
    (scripts/test_summary.py shows those lines)."""
    try:
        from rosunit.xmlrunner import _XMLTestResult
    except ImportError:
        return
    add_error = _XMLTestResult.addError

    def add_error_kept(result, test, err):
        if isinstance(test, unittest.suite._ErrorHolder):
            message = (str(err[1]).splitlines() or [''])[0]
            sys.stderr.write('%s %s: %s: %s\n%s' % (FIXTURE_ERROR, test.description, err[0].__name__, message,
                                                    result._exc_info_to_string(err, test)))
        add_error(result, test, err)
    _XMLTestResult.addError = add_error_kept


# every test node imports this module: an error in a class fixture keeps its message
keep_class_fixture_errors()


def wait_for(condition, what, timeout=30.0, poll=0.01):
    """Poll ``condition()`` until true; AssertionError naming ``what`` after ``timeout`` s wall
    (``what`` may be a callable, asked only then, to say what was seen instead)."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline or rospy.is_shutdown():
            raise AssertionError('gave up after %.0f s (wall): %s'
                                 % (timeout, what() if callable(what) else what))
        time.sleep(poll)

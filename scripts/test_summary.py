#!/usr/bin/env python3
"""Summarise catkin's xunit results: one line per failure, then `N passed, N failed`.

Counts every case of the pytest unit results (pytest-*.xml), of the package
lint (lint-*.xml, scripts/catkin_lint_junit.py) and of each rostest test node
(rosunit-*.xml); a rostest <test> node that wrote no results counts as
its rostest-*.xml entry (a failure), and errors a suite counts outside its
test cases (a setUpClass that raised: errors="1" and no case) count as one
failure, shown with the fixtures' error lines of the suite's system-err.
Exits 1 when a test failed or none ran.
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET

#: test/rostest/waiting.py's mark of a class fixture's error line in system-err
FIXTURE_ERROR = 'CLASS FIXTURE ERROR'


def cases(path):
    root = ET.parse(path).getroot()
    suites = [root] if root.tag == 'testsuite' else root.iter('testsuite')
    for suite in suites:
        for case in suite.iter('testcase'):
            yield suite, case
        unclaimed = _unclaimed_problems(suite)
        if unclaimed:
            # e.g. a rosunit suite whose setUpClass raised: errors="1", no test case
            case = ET.Element('testcase', classname=suite.get('name', '?'), name='(outside any test case)')
            ET.SubElement(case, 'error', message='%d error(s)/failure(s) the suite counts outside its test '
                          'cases (setUpClass or tearDownClass?): %s' % (unclaimed, _fixture_errors(suite)))
            yield suite, case


def _fixture_errors(suite):
    """The class fixtures' error lines in the suite's system-err (as the rostest nodes
    print them: test/rostest/waiting.py), else its last line, else a pointer to the log."""
    text = (suite.findtext('system-err') or '').replace('<![CDATA[', '').replace(']]>', '')
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    marked = [line[len(FIXTURE_ERROR):].strip() for line in lines if line.startswith(FIXTURE_ERROR)]
    if marked:
        return '; '.join(marked)
    return lines[-1] if lines else "see the test's log"


def _unclaimed_problems(suite):
    """Errors and failures a testsuite element counts beyond those of its own test cases."""
    try:
        counted = int(suite.get('errors') or 0) + int(suite.get('failures') or 0)
    except ValueError:
        return 0
    own = sum(len(case.findall('error')) + len(case.findall('failure'))
              for case in suite.findall('testcase'))
    return max(0, counted - own)


def outcome(case):
    """'failed' with a message, 'skipped' or 'passed' for one xunit testcase."""
    problem = case.find('failure')
    if problem is None:
        problem = case.find('error')
    if problem is not None:
        text = (problem.get('message') or problem.text or '').strip().splitlines()
        return 'failed', text[0][:300] if text else ''
    if case.find('skipped') is not None:
        return 'skipped', ''
    return 'passed', ''


def result_files(results_dir):
    """pytest files, each test node's rosunit file, and the rostest entry of any
    <test> node that produced no rosunit file (it crashed or timed out)."""
    files = glob.glob(os.path.join(results_dir, 'pytest-*.xml'))
    files += glob.glob(os.path.join(results_dir, 'lint-*.xml'))
    files += glob.glob(os.path.join(results_dir, 'rosunit-*.xml'))
    files += glob.glob(os.path.join(results_dir, 'MISSING-*.xml'))
    fallbacks = []
    for path in glob.glob(os.path.join(results_dir, 'rostest-*.xml')):
        try:
            for _, case in cases(path):
                test_name = case.get('name', '')[len('test'):]
                if not os.path.exists(os.path.join(results_dir, 'rosunit-%s.xml' % test_name)):
                    fallbacks.append((path, case))
        except ET.ParseError:
            files.append(path)
    return sorted(files), fallbacks


def main(results_dir):
    files, fallbacks = result_files(results_dir)
    counts = {'passed': 0, 'failed': 0, 'skipped': 0}
    found = list(fallbacks)
    for path in files:
        try:
            found += [(path, case) for _, case in cases(path)]
        except ET.ParseError as error:
            print('FAILED %s: unreadable result file (%s)' % (os.path.basename(path), error))
            counts['failed'] += 1
    for path, case in found:
        state, message = outcome(case)
        counts[state] += 1
        if state == 'failed':
            print('FAILED %s %s.%s: %s' % (os.path.basename(path), case.get('classname'),
                                           case.get('name'), message))
    passed, failed, skipped = counts['passed'], counts['failed'], counts['skipped']
    line = '%d passed, %d failed' % (passed, failed)
    if skipped:
        line += ', %d skipped' % skipped
    print(line)
    return 1 if failed or not passed else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else '.'))

"""Copy a rostest run's result files into catkin's results dir under a prefix, so
that a second run of the same tests (a Python lane, scripts/python_lane.sh)
counts beside the first: rosunit-NAME.xml -> rosunit-PREFIXNAME.xml, and the
rostest-*.xml entry of each test node (testNAME, scripts/test_summary.py's
fallback when a node wrote no result) -> testPREFIXNAME in rostest-PREFIX*.xml.

Usage: /usr/bin/python3 scripts/lane_results.py RUN_DIR RESULTS_DIR PREFIX
When RUN_DIR holds no rostest result (rostest did not start), writes a failed
MISSING-PREFIX*.xml case instead and exits 1.
"""
import glob
import os
import shutil
import sys
import xml.etree.ElementTree as ET

from junit_case import write_case


def copy_results(run_dir, results_dir, prefix):
    rostest_files = glob.glob(os.path.join(run_dir, 'rostest-*.xml'))
    for path in glob.glob(os.path.join(run_dir, 'rosunit-*.xml')):
        name = os.path.basename(path)[len('rosunit-'):]
        shutil.copyfile(path, os.path.join(results_dir, 'rosunit-' + prefix + name))
    for path in rostest_files:
        target = os.path.join(results_dir, 'rostest-' + prefix + os.path.basename(path)[len('rostest-'):])
        try:
            tree = ET.parse(path)
        except ET.ParseError:
            shutil.copyfile(path, target)  # the summary counts an unreadable file as a failure
            continue
        for case in tree.getroot().iter('testcase'):
            case.set('name', 'test' + prefix + case.get('name', '')[len('test'):])
        tree.write(target, encoding='utf-8', xml_declaration=True)
    return len(rostest_files)


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    run_dir, results_dir, prefix = argv[1:]
    if not copy_results(run_dir, results_dir, prefix):
        message = 'no rostest result in %s' % run_dir
        print('lane_results: ' + message)
        name = os.path.basename(os.path.dirname(os.path.abspath(run_dir)))
        write_case(os.path.join(results_dir, 'MISSING-%s%s.xml' % (prefix, name)), 'rostest',
                   'rostest ' + name, run_dir, 1, [message], '')
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))

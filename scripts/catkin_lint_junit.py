"""Run catkin_lint --strict -W2 on the package and record the outcome as one xunit
test case, so that make test counts a lint problem as a failed test.

Usage: /usr/bin/python3 scripts/catkin_lint_junit.py PACKAGE_DIR RESULT_XML
PACKAGE_DIR must be named after the package (catkin_lint reports a directory
named otherwise): make test lints the workspace's src/blind_navigation.
Exit status: catkin_lint's (0 when it found no problem).
"""
import subprocess
import sys

from junit_case import write_case

COMMAND = ['catkin_lint', '--strict', '-W2']
#: catkin_lint's own notices when rosdep is not installed: not problems of the package
ROSDEP_NOTICES = ('cannot load rosdep database', 'unknown dependencies will be ignored')


def lint(package_dir):
    """(exit status, problem lines, full output) of catkin_lint on ``package_dir``."""
    try:
        run = subprocess.run(COMMAND + [package_dir], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, universal_newlines=True, timeout=300)
    except FileNotFoundError:
        return 127, ['catkin_lint is not installed (Debian: catkin-lint; pip: catkin_lint)'], ''
    lines = [line for line in run.stdout.splitlines() if line.strip()]
    problems = [line for line in lines if ': error: ' in line or ': warning: ' in line
                or ': notice: ' in line or line.startswith('catkin_lint: error')]
    if run.returncode != 0 and not problems:
        problems = [line for line in lines if not any(n in line for n in ROSDEP_NOTICES)] or \
            ['catkin_lint exited %d' % run.returncode]
    return run.returncode, problems, run.stdout


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    package_dir, result = argv[1], argv[2]
    status, problems, output = lint(package_dir)
    for line in problems:
        print('catkin_lint: %s' % line)
    print('catkin_lint --strict -W2 %s: %s' % (
        package_dir, 'clean' if status == 0 else '%d problem(s)' % len(problems)))
    write_case(result, 'catkin_lint', ' '.join(COMMAND), package_dir, status, problems, output)
    return status


if __name__ == '__main__':
    sys.exit(main(sys.argv))

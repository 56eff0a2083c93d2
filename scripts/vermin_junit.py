"""Run vermin (requirements/tools.txt, in $BN_WS/venvs/tools) over the package, its
tests and scripts against Python 3.8 (ROS Noetic on Ubuntu 20.04) and record the
outcome as one xunit test case, so that make test counts a violation as a failed test.

Usage: /usr/bin/python3 scripts/vermin_junit.py VERMIN REPO RESULT_XML
Exit status: vermin's (0 when nothing needs a Python newer than 3.8).
"""
import os
import subprocess
import sys

from junit_case import report

#: --eval-annotations: annotations count as evaluated (no `list[int]` anywhere);
#: library members and keyword arguments (bisect's key=) are checked by default
OPTIONS = ['-t=3.8-', '--no-tips', '--violations', '--eval-annotations']
PATHS = ('blind_navigation', 'test', 'scripts')


def check(vermin, repo):
    """(exit status, violation lines, full output) of vermin on the repo's PATHS."""
    command = [vermin] + OPTIONS + [os.path.join(repo, p) for p in PATHS]
    try:
        run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True, timeout=300)
    except FileNotFoundError:
        return 127, ['%s is not installed (make deps: scripts/install_deps.sh)' % vermin], ''
    lines = run.stdout.splitlines()
    # a violation: the file's line ("!2, 3.10  path") and its reasons, indented below it
    problems = [line.strip() for line in lines if line.startswith('  ') or line.startswith('!')]
    if run.returncode != 0 and not problems:
        problems = lines[-3:] or ['vermin exited %d' % run.returncode]
    return run.returncode, problems, run.stdout


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    vermin, repo, result = argv[1:]
    return report(result, 'vermin', 'vermin %s' % ' '.join(OPTIONS), ' '.join(PATHS),
                  check(vermin, repo))


if __name__ == '__main__':
    sys.exit(main(sys.argv))

"""Run vulture (requirements/tools.txt, in $BN_WS/venvs/tools) at 60 % confidence with
the whole repo as context and record, as one xunit test case, what it finds unused in
the product (core/, ros/, nodes/, names.py); scripts/vulture_whitelist.py lists its
false positives (ROS handles kept on self, OSError.filename).

Usage: /usr/bin/python3 scripts/vulture_junit.py VULTURE REPO RESULT_XML
Exit status: 0 when nothing in the product is unused, else 1.
"""
import os
import subprocess
import sys

from junit_case import report

OPTIONS = ['--min-confidence', '60']
CONTEXT = ('blind_navigation', 'test', 'scripts')
PRODUCT = tuple(os.path.join('blind_navigation', part) for part in ('core/', 'ros/', 'nodes/', 'names.py'))


def check(vulture, repo):
    """(exit status, problem lines in the product, full output)."""
    command = ([vulture] + OPTIONS + [os.path.join(repo, p) for p in CONTEXT]
               + [os.path.join(repo, 'scripts', 'vulture_whitelist.py')])
    try:
        run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True, timeout=300)
    except FileNotFoundError:
        return 127, ['%s is not installed (make deps: scripts/install_deps.sh)' % vulture], ''
    lines = [os.path.relpath(line, repo) if line.startswith(repo) else line
             for line in run.stdout.splitlines()]
    problems = [line for line in lines if line.startswith(PRODUCT)]
    if run.returncode not in (0, 3):     # 3: found something (anywhere); else vulture failed
        problems = problems or lines[-3:] or ['vulture exited %d' % run.returncode]
    return (1 if problems else 0), problems, run.stdout


def main(argv):
    if len(argv) != 4:
        sys.exit(__doc__)
    vulture, repo, result = argv[1:]
    return report(result, 'vulture', 'vulture %s' % ' '.join(OPTIONS), ' '.join(PRODUCT),
                  check(vulture, os.path.abspath(repo)))


if __name__ == '__main__':
    sys.exit(main(sys.argv))

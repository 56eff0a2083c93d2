"""One xunit test case for a whole check (a linter's run), so that make test counts a
problem it finds as a failed test (scripts/test_summary.py reads lint-*.xml).

write_case(path, suite, command, target, status, problems, output, skipped=None): ``command``
ran on ``target`` and exited ``status``; ``problems`` are its problem lines, ``output`` all it
said; ``skipped``, a reason, marks a check that could not run here (a skipped case).
"""
import os
import xml.etree.ElementTree as ET


def write_case(path, suite_name, command, target, status, problems, output, skipped=None):
    suite = ET.Element('testsuite', name=suite_name, tests='1', failures='1' if status else '0',
                       errors='0', skipped='1' if skipped else '0')
    case = ET.SubElement(suite, 'testcase', classname=suite_name, name=command)
    if skipped:
        ET.SubElement(case, 'skipped', message=skipped)
    if status:
        failure = ET.SubElement(case, 'failure', message='%d problem(s): %s' % (
            len(problems), problems[0] if problems else 'exit %d' % status))
        failure.text = output or '\n'.join(problems)
    ET.SubElement(case, 'system-out').text = '%s %s\n%s' % (command, target, output)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding='utf-8', xml_declaration=True)


def report(result, tool, name, target, checked):
    """Print ``checked`` (status, problem lines, output of ``name``, a run of ``tool`` on
    ``target``), one line each and a verdict, and write it as one case to ``result``;
    return the status."""
    status, problems, output = checked
    for line in problems:
        print('%s: %s' % (tool, line))
    print('%s %s: %s' % (name, target, 'clean' if status == 0 else '%d line(s)' % len(problems)))
    write_case(result, tool, name, target, status, problems, output)
    return status

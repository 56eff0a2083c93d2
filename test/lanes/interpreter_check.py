#!/usr/bin/env python3
"""A Python lane's check (scripts/python_lane.sh; run by lane_mission.py): every node
of the test's launch runs under the lane's Python.

Waits until the master lists each of ``~nodes`` (the layer's), then asks each
for its pid and reads the process's executable (/proc/PID/exe). Asserted: this
test script runs under Python ``~python`` (it was started as `#!/usr/bin/env
python3`, like the package's test scripts), and every one of ``~nodes`` runs
under this script's interpreter. The other nodes' interpreters are logged (the
fake TurtleBot's base and camera run under Debian's: scripts/python_lane.sh).
"""
import os
import sys
import unittest
import xmlrpc.client

import rosgraph
import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'rostest'))
from waiting import wait_for  # noqa: E402

NAME = 'interpreter_check'


def registered_nodes(master):
    state = master.getSystemState()
    return {node for entries in state for _, nodes in entries for node in nodes}


class InterpreterTest(unittest.TestCase):

    def test_every_node_runs_under_the_lane_python(self):
        expected = str(rospy.get_param('~python'))
        own = '%d.%d' % sys.version_info[:2]
        self.assertEqual(own, expected, 'this test script runs under Python %s (%s), not %s'
                         % (own, sys.executable, expected))
        master = rosgraph.Master(rospy.get_name())
        wanted = set(rospy.get_param('~nodes'))
        wait_for(lambda: wanted <= registered_nodes(master),
                 'the nodes %s on the master' % sorted(wanted - registered_nodes(master)),
                 timeout=float(rospy.get_param('~timeout', 60.0)))
        interpreter = os.path.realpath(sys.executable)
        found, wrong = {}, []
        for node in sorted(registered_nodes(master) - {'/rosout', rospy.get_name()}):  # C++ logger
            try:
                api = rosgraph.Master(rospy.get_name()).lookupNode(node)
                code, message, pid = xmlrpc.client.ServerProxy(api).getPid(rospy.get_name())
            except (OSError, rosgraph.MasterError) as error:    # a helper that has just ended
                code, message = 0, str(error)
            if code != 1 and node not in wanted:
                rospy.logwarn('interpreter_check: %s not asked: %s', node, message)
                continue
            self.assertEqual(code, 1, 'getPid of %s: %s' % (node, message))
            found[node] = os.path.realpath('/proc/%d/exe' % pid)
            if node in wanted and found[node] != interpreter:
                wrong.append('%s (pid %d): %s' % (node, pid, found[node]))
        rospy.loginfo('interpreter_check: %s', ', '.join('%s %s' % item for item in sorted(found.items())))
        self.assertFalse(wrong, 'nodes not under %s: %s' % (interpreter, '; '.join(wrong)))
        self.assertTrue(wanted <= set(found), 'checked %s, wanted %s' % (sorted(found), sorted(wanted)))


if __name__ == '__main__':
    rospy.init_node(NAME)
    rostest.rosrun('blind_navigation', NAME, InterpreterTest)

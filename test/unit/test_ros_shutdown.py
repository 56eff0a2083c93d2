"""ros/faults.shutting_down: true inside the rospy.on_shutdown hooks, where
rospy.is_shutdown() is still false. The roles' worker threads wait on events
that such a hook sets; one that asked rospy.is_shutdown() took the shutdown
wake-up for work (rotate_pi logged a new pi turn after the mission had come home,
back_travel_client could start a return). Run in a child process: a shutdown
cannot be undone in this one."""
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = '''
import rospy
from blind_navigation.ros.faults import shutting_down
seen = []
rospy.on_shutdown(lambda: seen.append((rospy.is_shutdown(), shutting_down())))
print('before', rospy.is_shutdown(), shutting_down())
rospy.signal_shutdown('test')
print('in the hook', *seen[0])
print('after', rospy.is_shutdown(), shutting_down())
'''


def test_shutting_down_is_true_in_the_shutdown_hooks_where_is_shutdown_is_not_yet():
    run = subprocess.run([sys.executable, '-c', SCRIPT], cwd=REPO, capture_output=True, text=True,
                         timeout=60)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == ['before False False', 'in the hook False True', 'after True True']

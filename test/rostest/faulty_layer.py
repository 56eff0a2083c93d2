#!/usr/bin/env python3
"""Test-only (role_failure_*.test): a layer node run by its normal main()
(nodes/mission_owner.py, the one process; or the node script named by the second
argument, e.g. rotate_pi.py of the paper's layout), with ONE method of one role's code
made to raise, as a bug would. The first argument names the fault (:data:`FAULTS`):

- ``client``: the client's route building after vision loss raises Python 3.8's
  TypeError of bisect(key=) (core/pruning.prune_route as core/return_plan calls it,
  in the client's thread: issue 21's report);
- ``server``: the back-travel server's control step raises mid-return
  (core/route_follower.RouteFollower.step, after AFTER_STEPS steps);
- ``rotate``: rotate_pi's turn step raises mid-turn (core/rotation.Rotation.step).
"""
import runpy
import sys

import roslib.packages
import rospy

from blind_navigation.core import return_plan
from blind_navigation.core.rotation import Rotation
from blind_navigation.core.route_follower import RouteFollower

#: control steps (50 Hz) before the step raises: the robot is moving by then
AFTER_STEPS = 60
#: the message of the client's fault: what Python 3.8 raised in core/pruning.py
BISECT_KEY = "'key' is an invalid keyword argument for bisect_left()"


def raising_after(method, steps, error):
    """``method`` that raises ``error`` from its ``steps``-th call on."""
    calls = [0]

    def step(self, *args, **kwargs):
        calls[0] += 1
        if calls[0] >= steps:
            raise error
        return method(self, *args, **kwargs)
    return step


def pruned(route, landmarks, correction, params):
    raise TypeError(BISECT_KEY)


FAULTS = {
    'client': lambda: setattr(return_plan, 'prune_route', pruned),
    'server': lambda: setattr(RouteFollower, 'step', raising_after(
        RouteFollower.step, AFTER_STEPS, ZeroDivisionError('injected in the control step'))),
    'rotate': lambda: setattr(Rotation, 'step', raising_after(
        Rotation.step, AFTER_STEPS, RuntimeError('injected in the turn step'))),
}


def main():
    args = rospy.myargv(sys.argv)
    if len(args) not in (2, 3) or args[1] not in FAULTS:
        sys.exit('usage: faulty_layer.py %s [NODE_SCRIPT] [ROS args]' % '|'.join(sorted(FAULTS)))
    FAULTS[args[1]]()
    script = args[2] if len(args) == 3 else 'mission_owner.py'
    found = roslib.packages.find_node('blind_navigation', script)
    if not found:
        sys.exit('%s not found in package blind_navigation' % script)
    sys.argv = [found[0]] + [arg for arg in sys.argv[1:] if arg not in args[1:]]
    runpy.run_path(found[0], run_name='__main__')


if __name__ == '__main__':
    main()

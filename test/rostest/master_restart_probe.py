"""The observer of safety_findings.test's finding 7d (a helper, not a test): a node on a
master of its own (the test's subprocess world: that master, the fake TurtleBot and the
layer), run with /usr/bin/python3 by the test, which restarts that master when asked.

It starts the recording (it listens to the samples, the rig's second listener), starts
the scripted operator, prints ``PROBE {"event": "restart_master"}`` a few seconds into
the recording and waits for a line on stdin (the master was restarted); then, when
the operator is done, it triggers vision loss on the connection made before the
restart, waits for ``home`` or ``aborted`` and watches the robot. Its last line is
``PROBE {"event": "summary", ...}``: the states, the final reason, the sim times, the
layer's motion commands after the terminal state, and how far the robot moved and
turned after it (findings_rig.FindingMission.still_after's verdict).
"""
import json
import os
import subprocess
import sys

import roslib.packages
import rospy
from geometry_msgs.msg import Twist
from std_msgs.msg import Bool, Empty, String

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from findings_rig import (MISSION, SETTLE, Track, layer_commands,  # noqa: E402
                          moving_commands_after)
from mission_tools import MISSION_DONE_TOPIC, TELEOP_TOPIC  # noqa: E402
from recording_tools import Collector, subscribers_of  # noqa: E402
from waiting import wait_for  # noqa: E402

from blind_navigation import names  # noqa: E402
from blind_navigation.core.mission_state import TERMINAL  # noqa: E402
from blind_navigation.msg import MissionStatus, PathSample  # noqa: E402

WALL_TIMEOUT = 120.0
#: s of sim time recorded before the master is restarted
RECORD_BEFORE_RESTART = 5.0
#: s of sim time watched after the terminal state
WATCH = 4.0


def emit(event, **data):
    print('PROBE ' + json.dumps(dict(data, event=event)), flush=True)


def wait_sim(seconds, what):
    until = rospy.get_time() + seconds
    wait_for(lambda: rospy.get_time() >= until, what, WALL_TIMEOUT)


def main():
    rospy.init_node('master_restart_probe')
    states = Collector(names.STATE, String)
    status = Collector(names.STATUS, MissionStatus)
    commands = Collector(TELEOP_TOPIC, Twist)
    done = Collector(MISSION_DONE_TOPIC, Bool)
    track = Track()
    trigger = rospy.Publisher(names.VISION_LOST, Empty, queue_size=1)
    owner = '/blind_navigation'
    wait_for(lambda: states.snapshot(), 'the layer publishes its state', WALL_TIMEOUT)
    wait_for(lambda: owner in subscribers_of(names.VISION_LOST) and trigger.get_num_connections() >= 1,
             'the trigger is connected to the mission owner', WALL_TIMEOUT)
    rospy.Subscriber(names.SAMPLE, PathSample, lambda _msg: None)     # the recording starts
    wait_for(lambda: 'recording' in [m.data for m in states.snapshot()], 'state recording', WALL_TIMEOUT)
    found = roslib.packages.find_node('blind_navigation', 'mission_driver.py')
    operator = subprocess.Popen([found[0], '__name:=mission_driver', '_mission:=%s' % MISSION,
                                 'cmd_vel:=%s' % TELEOP_TOPIC, 'ground_truth:=/ground_truth/odom'])
    try:
        wait_for(lambda: done.snapshot(), 'the operator is up', WALL_TIMEOUT)
        wait_sim(RECORD_BEFORE_RESTART, 'recording before the master restart')
        emit('restart_master', at=rospy.get_time())
        sys.stdin.readline()
        restarted = rospy.get_time()
        wait_for(lambda: any(m.data for m in done.snapshot()), 'the operator is done', WALL_TIMEOUT)
        wait_sim(2.0, 'the robot stops')
        trigger.publish(Empty())
        wait_for(lambda: set(TERMINAL) & {m.data for m in states.snapshot()},
                 'state home or aborted', WALL_TIMEOUT)
        final_at = [t for t, m in list(states.items) if m.data in TERMINAL][0]
        wait_sim(SETTLE + WATCH, 'the watch after the terminal state')
        moved, turned = track.motion(final_at + SETTLE, final_at + SETTLE + WATCH)
        late = moving_commands_after(layer_commands(commands), final_at)
        rotating_at = [t for t, m in list(states.items) if m.data == 'rotating']
        recording_at = [t for t, m in list(states.items) if m.data == 'recording'][0]
        emit('summary', states=[m.data for m in states.snapshot()], recording_at=recording_at,
             reason=(status.snapshot() or [MissionStatus()])[-1].reason, restarted=restarted,
             final_at=final_at, late=len(late), moved=moved, turned=turned,
             turned_after_loss=track.turned(rotating_at[0], final_at) if rotating_at else 0.0,
             displaced=track.motion(rotating_at[0], final_at + SETTLE + WATCH)[0] if rotating_at else 0.0,
             home_error=_distance(track.at(recording_at), track.at(final_at + SETTLE)))
    finally:
        operator.terminate()
        operator.wait(10.0)


def _distance(a, b):
    return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5


if __name__ == '__main__':
    main()

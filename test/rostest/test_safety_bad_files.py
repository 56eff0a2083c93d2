"""Test cases of safety_stops.test (its node runs them first): each bad landmark file is refused: state ``aborted``, the reason
names the file and the entry, no goal is sent and no velocity is published.
A file that already gives no way back is refused at the vision loss, before the
pi turn (issue 28: no ``rotating``, no progress file); one that holds no landmark
yet (the final landmark comes when the turn begins) when the return starts.
One client per case (topics remapped under /bad_<case>), all in parallel,
against one back_travel_server and the ideal base, which the test turns by pi
once every client that waits for it has moved to rotating (each client checks
the real turn before it returns). The clock and the base are the node's
(safety_rig.shared_rig), shared with test_safety_stops.py's cases."""
import math
import os
import shutil
import unittest

import rospy

from blind_navigation.core.progress import load_progress, progress_path
from blind_navigation.msg import BackTravelActionGoal

from safety_rig import CLIENT_PARAMS, Collector, Layer, Node, shared_rig

HEADER = "blind_navigation: {format: 1, fields: [v, w, d, T, psi]}\n"
GOOD = "landmark_000001: {data: [0.1, 0.0, 0.2, 2.0, 0.0]}\n"

#: case -> (file text, None = no file; substrings the abort reason must hold): one file the
#: client cannot read, one refused at the vision loss by a rule (a limit and finding 1's
#: d ~ 1e6), one judged at the return's start. Every other refusal's message is the loader's
#: (test/unit/test_store.py's BAD_FILES: empty, not YAML, a wrong type, not five numbers, NaN,
#: inf, negative d, zero T; test_plausibility.py's finding 2: |w| beyond the limit).
CASES = {
    'missing': (None, ['cannot read']),
    'truncated': (HEADER + 'landmark_000001: {data: [0.1, 0.0', ['no landmarks', 'torn']),
    'too_fast': (HEADER + GOOD + "landmark_000002: {data: [0.9, 0.0, 1.8, 2.0, 0.0]}\n",
                 ['landmark_000002', '|v| = 0.9 m/s exceeds the limit 0.7 m/s']),
    # issue 16, finding 1: a burst of odometry at x = 1e6 gave landmarks with d ~ 1e6
    'too_far': (HEADER + GOOD + "landmark_000002: {data: [0.1, 0.0, 1000000.0, 2.0, 0.0]}\n",
                ['landmark_000002', 'd = 1e+06 m is farther than the base can go in T = 2 s']),
}
TOPICS = ('state', 'storage', 'vision_lost', 'rotation_done')
#: Cases whose file holds no landmark yet: judged when the return starts, after the turn.
NO_LANDMARK_YET = ('truncated',)


class BadFilesTest(unittest.TestCase):

    def test_each_bad_file_is_refused_with_its_message_and_no_motion(self):
        _clock, base, _layer = shared_rig()
        directory = os.path.join(rospy.get_param('~directory'), 'bad_files')
        shutil.rmtree(directory, ignore_errors=True)
        os.makedirs(directory)
        commands = len(base.commands)
        goals = Collector('/blind_navigation/back_travel/goal', BackTravelActionGoal)
        layers, nodes, files = {}, [], {}
        for case, (text, _) in CASES.items():
            files[case] = os.path.join(directory, case + '.yaml')
            if text is not None:
                with open(files[case], 'w') as stream:
                    stream.write(text)
            prefix = '/bad_' + case
            layers[case] = Layer(prefix)
            nodes.append(Node('back_travel_client.py', 'client_' + case,
                              dict(CLIENT_PARAMS, landmark_file=files[case]),
                              {'/blind_navigation/' + t: prefix + '/' + t for t in TOPICS}))
        try:
            for case, layer in layers.items():
                layer.walk_to_rotating(0, timeout=90.0, target='rotating' if case in NO_LANDMARK_YET
                                       else 'aborted')
            base.turn(math.pi)
            for case in NO_LANDMARK_YET:
                layers[case].finish_rotation(0, timeout=90.0)
            for case, layer in layers.items():
                self.assertEqual(layer.wait_final(0, timeout=60.0), 'aborted', case)
                if case not in NO_LANDMARK_YET:
                    self.assertEqual(layer.state_list(0), ['idle', 'recording', 'aborted'], case)
                reason = layer.abort_reason('/client_' + case)
                print('BAD FILE %s: %s' % (case, reason), flush=True)
                for text in [files[case]] + CASES[case][1]:
                    self.assertIn(text, reason, 'case %s' % case)
        finally:
            for node in nodes:
                node.kill()
        goals.sub.unregister()
        self.assertEqual(len(goals), 0, 'a goal was sent for a bad file')
        self.assertEqual(base.commands[commands:], [], 'a velocity was published for a bad file')
        # (the turn by pi is the test's own, inside the fake base: no command)
        # a return refused before the turn never began: no progress to resume
        progress = {case + '.progress.yaml' for case in NO_LANDMARK_YET}    # next to the landmark file
        recorded = {os.path.basename(f) for c, f in files.items() if CASES[c][0] is not None}
        self.assertEqual(set(os.listdir(directory)), recorded | progress,
                         'the layer wrote something besides its progress files')
        for case in NO_LANDMARK_YET:
            self.assertEqual(load_progress(progress_path(files[case])).status, 'aborted', case)


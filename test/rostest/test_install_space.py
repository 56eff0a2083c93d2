#!/usr/bin/env python3
"""rostest (install_space.test): the package as a user gets it from `catkin_make install`.

Builds the package in a fresh workspace (the package's source linked in) with
`catkin_make install`, in an environment that knows only the system's ROS (no devel
space of the workspace running the tests; scripts/install_space.sh): in a temporary
directory, or make test's build beside the rostests (BN_INSTALL_SPACE names its
workspace: the test waits for its status file). Then, sourcing only
install/setup.bash: the package, its Python modules and its launch files resolve to
install/, only the layer's nodes and the test rig's are installed (no dev script), and
the shipped demo.launch runs a mission to `home` from there without an [ERROR] line
(DEMO_SCENARIO: the install is proved, not a table's accuracy).
"""
import os
import re
import shutil
import socket
import subprocess
import tempfile
import unittest

import rospkg
import rospy
import rostest

from waiting import wait_for


PACKAGE = 'blind_navigation'
#: s of wall time: the build (messages, the C++ tool) and the demo mission (rtf 5)
BUILD_TIMEOUT = 240.0
DEMO_TIMEOUT = 240.0
#: the demo's mission: the 2.3 m test mission at 0.15 m/s (its default, Table VI test 1, is
#: 2.6 m at 0.086 m/s)
DEMO_SCENARIO = 'test_safety'
#: what install/lib/blind_navigation must hold: every node launch files start, and the tool
INSTALLED = {'mission_owner.py', 'back_travel_client.py', 'back_travel_server.py',
             'calibrate_gyro.py', 'heading_correction.py', 'landmark_saver.py', 'record_client.py',
             'record_server.py', 'rotate_pi.py', 'sampling_publisher.py', 'vision_monitor.py',
             'cmd_vel_mux.py', 'fake_dock_drive.py', 'fake_kobuki.py', 'fake_vision.py', 'mission_driver.py',
             'demo_observer.py', 'bench_probe.py', 'landmark_info'}
#: the system's ROS: Debian's packages live in /usr; Noetic's setup, when present
SYSTEM_SETUP = '[ -f /opt/ros/noetic/setup.bash ] && source /opt/ros/noetic/setup.bash; '


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


class InstallSpaceTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.ws = os.environ.get('BN_INSTALL_SPACE') or tempfile.mkdtemp(prefix='bn_install_')
        cls.install = os.path.join(cls.ws, 'install')
        status = os.path.join(cls.ws, 'build.status')
        if 'BN_INSTALL_SPACE' not in os.environ:
            script = os.path.join(rospkg.RosPack().get_path(PACKAGE), 'scripts', 'install_space.sh')
            subprocess.run(['bash', script, cls.ws], timeout=BUILD_TIMEOUT)
        wait_for(lambda: os.path.exists(status), 'the install space build (%s)' % status, BUILD_TIMEOUT, poll=0.5)
        with open(status) as code, open(os.path.join(cls.ws, 'build.log')) as log:
            cls.build = int(code.read()), log.read()

    @classmethod
    def tearDownClass(cls):
        if 'BN_INSTALL_SPACE' not in os.environ:
            shutil.rmtree(cls.ws, ignore_errors=True)

    @classmethod
    def run_clean(cls, script, timeout, installed=False):
        """``script`` in bash with a clean environment (PATH, HOME, a private ROS_HOME and
        master); ``installed``: after sourcing install/setup.bash only."""
        env = {'PATH': '/usr/bin:/bin', 'HOME': os.environ.get('HOME', cls.ws), 'LANG': 'C.UTF-8',
               'WS': cls.ws, 'ROS_PYTHON_VERSION': '3', 'ROS_HOME': os.path.join(cls.ws, 'ros_home'),
               'ROS_LOG_DIR': os.path.join(cls.ws, 'log'),
               'ROS_MASTER_URI': 'http://localhost:%d' % free_port()}
        if installed:
            script = SYSTEM_SETUP + 'source "$WS/install/setup.bash"; ' + script
        try:
            run = subprocess.run(['bash', '-c', script], env=env, stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, universal_newlines=True, timeout=timeout)
        except subprocess.TimeoutExpired as error:
            raise AssertionError('%r did not end within %.0f s; output ends:\n%s'
                                 % (script, timeout, (error.output or '')[-3000:]))
        return run.returncode, run.stdout

    def assert_ran(self, result, what):
        status, output = result
        self.assertEqual(status, 0, '%s exited %d; output ends:\n%s' % (what, status, output[-3000:]))
        return output

    def test_1_catkin_make_install_succeeds(self):
        self.assert_ran(self.build, 'catkin_make install')

    def test_2_package_and_modules_resolve_to_install(self):
        self.assert_ran(self.build, 'catkin_make install')
        output = self.assert_ran(self.run_clean(
            'rospack find %s; /usr/bin/python3 -c "import blind_navigation.msg, blind_navigation.ros.layer as m; '
            'print(m.__file__)"' % PACKAGE, 60.0, installed=True), 'rospack find / import')
        share, module = output.split()[-2:]
        self.assertEqual(os.path.realpath(share), os.path.realpath(os.path.join(self.install, 'share', PACKAGE)))
        self.assertTrue(os.path.realpath(module).startswith(os.path.realpath(self.install)), module)

    def test_3_only_nodes_are_installed_and_the_shared_directories(self):
        self.assert_ran(self.build, 'catkin_make install')
        programs = set(os.listdir(os.path.join(self.install, 'lib', PACKAGE)))
        self.assertEqual(programs, INSTALLED)
        share = os.path.join(self.install, 'share', PACKAGE)
        for path in ('launch/demo.launch', 'launch/rtabmap_vo.launch', 'config/missions/table6_test1.yaml',
                     'config/noise/paper.yaml', 'rviz/blind_navigation.rviz', 'package.xml'):
            self.assertTrue(os.path.isfile(os.path.join(share, path)), path)

    def test_4_the_demo_comes_home_from_install(self):
        self.assert_ran(self.build, 'catkin_make install')
        results = os.path.join(self.ws, 'results')
        output = self.assert_ran(self.run_clean(
            'roslaunch %s demo.launch rtf:=5 scenario:=%s results_dir:="%s"' % (PACKAGE, DEMO_SCENARIO, results),
            DEMO_TIMEOUT, installed=True), 'roslaunch demo.launch')
        errors = [line for line in output.splitlines() if re.search(r'\[(ERROR|FATAL)\]', line)]
        self.assertEqual(errors, [])
        with open(os.path.join(results, 'demo_%s_closed_loop.txt' % DEMO_SCENARIO)) as stream:
            row = stream.read()
        self.assertIn('| home |', row)


if __name__ == '__main__':
    rospy.init_node('install_space_test')
    rostest.rosrun(PACKAGE, 'install_space', InstallSpaceTest)

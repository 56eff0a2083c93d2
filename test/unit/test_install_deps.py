"""A fresh machine has every command the tests, scripts, Makefile and launch files
call: each one found there comes (`dpkg -S`) from a package that
scripts/install_deps.sh names for this distribution (or an essential one), or
from a pinned venv that install_deps.sh makes."""
import os
import re
import shutil
import subprocess

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..'))
INSTALL_DEPS = os.path.join(REPO, 'scripts', 'install_deps.sh')
#: where calls are looked for
SOURCES = ('test', 'scripts', 'launch', 'blind_navigation', 'Makefile', 'CMakeLists.txt')
#: the external commands looked for (a call: a Python string 'cmd' or 'cmd ...', a shell word)
COMMANDS = ('rospack', 'rostopic', 'rosservice', 'rosnode', 'rosparam', 'roslaunch', 'rostest',
            'rosbag', 'rosrun', 'rosmsg', 'roscore', 'catkin_make', 'catkin_lint', 'cmake', 'make',
            'g++', 'mount', 'umount', 'sha1sum', 'dpkg-query', 'apt-get', 'apt-cache')
#: commands from the venvs install_deps.sh makes: command -> (venv, requirements file)
VENV_COMMANDS = {'vermin': ('tools', 'tools.txt'), 'vulture': ('tools', 'tools.txt')}
#: launch nodes of other packages that no test or make target starts: type -> why
#: (a package given by an arg, rtabmap_vo.launch's $(arg odom_pkg), is not resolved)
OPTIONAL_NODES = {'rviz': "rviz.launch, only with rviz:=true (default false): a desktop's choice",
                  'nodelet': "kobuki_safety_controller.launch: the real robot's Kobuki stack "
                             "(turtlebot2_noetic.rosinstall), not the tests"}
#: where ROS installs a package's node executables (libexec)
LIBEXEC = ('/opt/ros/noetic/lib', '/usr/lib')


def package_lists(text):
    """{'COMMON': [choice, ...], 'DEBIAN_ROS': ..., 'NOETIC_ROS': ...} of install_deps.sh."""
    code = '\n'.join(line.split('#')[0] for line in text.splitlines())
    return {name: [w.strip('"') for w in body.split()]
            for name, body in re.findall(r'^(\w+)=\((.*?)\)', code, re.S | re.M)}


def listed_packages(text, noetic=os.path.isfile('/opt/ros/noetic/setup.bash')):
    """The packages install_deps.sh installs here (either of each a|b choice)."""
    lists = package_lists(text)
    choices = lists['COMMON'] + lists['NOETIC_ROS' if noetic else 'DEBIAN_ROS']
    return {pkg for choice in choices for pkg in choice.split('|')}


def source_files():
    for source in SOURCES:
        path = os.path.join(REPO, source)
        if os.path.isfile(path):
            yield path
        for folder, dirs, names in os.walk(path):
            dirs[:] = [d for d in dirs if d != '__pycache__']
            yield from (os.path.join(folder, n) for n in sorted(names)
                        if n.endswith(('.py', '.sh', '.launch', '.test'))
                        and os.path.join(folder, n) != os.path.abspath(__file__.replace('.pyc', '.py')))


def calls(path, text):
    """{command: path} of COMMANDS called in one file, and the node executables of other
    packages its launch tags start, as {type: (pkg, path)}."""
    found, nodes = set(), {}
    for command in COMMANDS:
        word = re.escape(command)
        if path.endswith('.py'):
            pattern = r'''['"]%s(['"]| )''' % word
        elif path.endswith(('.launch', '.test')):
            pattern = r'launch-prefix="%s\b' % word
        else:  # shell: a word at a command's start
            pattern = r'(^|[;&|(`]|\$\(|then|do|&&)\s*%s(\s|$)' % word
        lines = (line.split('#')[0] if not path.endswith('.py') else line for line in text.splitlines())
        if any(re.search(pattern, line) for line in lines):
            found.add(command)
    for tag in re.findall(r'<(?:node|test)\b[^>]*>', text):
        attributes = dict(re.findall(r'(\w+)="([^"]*)"', tag))
        pkg, kind = attributes.get('pkg', ''), attributes.get('type', '')
        if pkg and '$' not in pkg and pkg != 'blind_navigation':
            nodes[kind] = pkg
    return found, nodes


def all_calls():
    commands, nodes = {}, {}
    for path in source_files():
        with open(path, errors='replace') as stream:
            text = stream.read()
        found, launched = calls(path, text)
        for command in found:
            commands.setdefault(command, os.path.relpath(path, REPO))
        for kind, pkg in launched.items():
            nodes.setdefault(kind, (pkg, os.path.relpath(path, REPO)))
    return commands, nodes


def owners(paths):
    """{path: the Debian package that installed it (or its target)} of ``paths`` (one
    `dpkg -S` for all: each call reads dpkg's whole database)."""
    # merged /usr: a package's /bin/x is found at /usr/bin/x
    candidates = {c: path for path in paths
                  for c in (path, os.path.realpath(path), re.sub('^/usr/', '/', path))}
    run = subprocess.run(['dpkg', '-S'] + sorted(candidates), stdout=subprocess.PIPE,
                         stderr=subprocess.DEVNULL, universal_newlines=True, timeout=60)
    found = {}
    for line in run.stdout.splitlines():
        package, _, path = line.partition(': ')
        if path in candidates:
            found.setdefault(candidates[path], package.split(',')[0].split(':')[0].strip())
    return found


def essential(packages):
    """The ``packages`` that every Debian system has (Essential or Priority required)."""
    run = subprocess.run(['dpkg-query', '-W', '-f=${Package} ${Essential} ${Priority}\n']
                         + sorted(packages), stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                         universal_newlines=True, timeout=60)
    return {fields[0] for fields in (line.split() for line in run.stdout.splitlines())
            if 'yes' in fields[1:] or 'required' in fields[1:]}


def unlisted(executables, packages):
    """[problem] for each {what: path-or-None} not from ``packages`` nor an essential package."""
    found = owners([path for path in executables.values() if path])
    given = essential(set(found.values()))
    problems = []
    for what, path in sorted(executables.items()):
        package = found.get(path)
        if path is None:
            problems.append('%s: not installed here' % what)
        elif package is None:
            problems.append('%s (%s): no Debian package installed it' % (what, path))
        elif package not in packages and package not in given:
            problems.append('%s (%s): from %s, which scripts/install_deps.sh does not install'
                            % (what, path, package))
    return problems


def executables_called():
    """{command or node type: its path here (None: missing)} of every call."""
    commands, nodes = all_calls()
    found = {'%s (%s)' % (c, where): shutil.which(c) for c, where in commands.items()
             if c not in VENV_COMMANDS}
    for kind, (pkg, where) in nodes.items():
        if kind in OPTIONAL_NODES:
            continue
        paths = [os.path.join(d, pkg, kind) for d in LIBEXEC if os.path.isfile(os.path.join(d, pkg, kind))]
        found['%s/%s node (%s)' % (pkg, kind, where)] = paths[0] if paths else None
    return found


needs_dpkg = pytest.mark.skipif(shutil.which('dpkg') is None, reason='not a Debian-based machine')


@needs_dpkg
def test_every_command_called_comes_from_a_package_install_deps_installs():
    with open(INSTALL_DEPS) as stream:
        packages = listed_packages(stream.read())
    called = executables_called()
    # the ROS commands the tests and scripts are known to call, so a broken search cannot
    # pass empty (rosnode is imported as a module; rosservice, rosmsg, rosrun are not called)
    for command in ('rospack', 'rostopic', 'rosparam', 'roslaunch', 'rostest', 'rosbag',
                    'catkin_make', 'catkin_lint'):
        assert any(key.startswith(command + ' (') for key in called), command
    problems = unlisted(called, packages)
    assert not problems, '\n'.join(problems)


@needs_dpkg
def test_a_package_missing_from_the_list_fails():
    with open(INSTALL_DEPS) as stream:
        text = stream.read()
    assert 'rospack-tools' in text and 'ros-noetic-rospack' in text
    packages = listed_packages(text) - {'rospack-tools', 'ros-noetic-rospack'}
    problems = unlisted({key: path for key, path in executables_called().items()
                         if key.startswith('rospack (')}, packages)
    assert len(problems) == 1 and 'does not install' in problems[0], problems


def test_the_venv_commands_come_from_venvs_install_deps_makes():
    with open(INSTALL_DEPS) as stream:
        text = stream.read()
    for command, (venv, requirements) in VENV_COMMANDS.items():
        assert re.search(r'^make_venv %s \S+ %s' % (venv, re.escape(requirements)), text, re.M), command
        with open(os.path.join(REPO, 'requirements', requirements)) as stream:
            assert re.search(r'^%s==\S+' % re.escape(command), stream.read(), re.M), command

"""Where the package's config/ directory (missions, noise profiles, recorded paths) is:
next to the sources in a checkout or a devel space, in the package's share directory
after `catkin_make install` (found through ROS_PACKAGE_PATH, as roslaunch finds it)."""
import os

import yaml

PACKAGE = 'blind_navigation'
SOURCE_CONFIG = os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..', 'config'))


def config_dir(*parts):
    """The path of ``config/<parts>``; the source tree's when it exists, else the installed
    package's (or the source path again when ROS cannot find the package: the caller's
    error then names it)."""
    base = SOURCE_CONFIG
    if not os.path.isdir(base):
        import rospkg
        try:
            base = os.path.join(rospkg.RosPack().get_path(PACKAGE), 'config')
        except rospkg.ResourceNotFound:
            pass
    return os.path.join(base, *parts)


def load_named(directory, name_or_path, what):
    """(path, data) of the YAML file ``name_or_path``: a name in ``directory`` (no '.yaml')
    or a path; ValueError naming ``what`` and the known names when it is not there."""
    path = name_or_path
    if os.path.sep not in name_or_path and not name_or_path.endswith('.yaml'):
        path = os.path.join(directory, name_or_path + '.yaml')
    if not os.path.isfile(path):
        known = sorted(f[:-5] for f in os.listdir(directory) if f.endswith('.yaml'))
        raise ValueError('%s %r not found (%s); known: %s' % (what, name_or_path, path, known))
    with open(path) as stream:
        return path, yaml.safe_load(stream) or {}

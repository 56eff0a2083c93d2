"""Where the package's config/ directory (missions, noise profiles, recorded paths) is:
next to the sources in a checkout or a devel space, in the package's share directory
after `catkin_make install` (found through ROS_PACKAGE_PATH, as roslaunch finds it)."""
import os

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

"""Mission files: each mission records into its own time-stamped file, and the
configured ``landmark_file`` is a symlink to the current one.

:func:`open_mission_file` continues the current mission's file (a recorder
restarted mid-mission) or starts a new one (:func:`start_mission_file`);
``new_mission`` numbers the missions of a launch (:func:`next_mission_id`);
nothing recorded is overwritten or deleted. Why: docs/recording.md, "File".
"""
import datetime
import os
import stat

import yaml

from .files import StorageError, describe_mode, read_regular_file, replace_with_symlink
from .landmark import Limits
from .landmark_format import MAX_FILE_BYTES, METADATA_KEY, OWN_LINES, LandmarkFileError, parse
from .landmark_writer import LandmarkWriter

#: Why a restarted recorder's first landmark breaks the d chain.
RESTART_GAP = ('the recorder restarted mid-mission: this landmark measures d from where the robot '
               'was at the restart, not from the previous landmark')


def next_mission_id(current):
    """The id of the mission after ``current`` (a launch's id, None, or one made here):
    ``<launch id>#<n>``, numbered on from ``current``'s."""
    launch, _, number = (current or '').rpartition('#')
    if launch and number.isdigit():
        return '%s#%d' % (launch, int(number) + 1)
    return '%s#2' % (current or 'mission')


def mission_number(current):
    """The number of mission ``current`` within its launch (1: the launch's own id)."""
    _, _, number = (current or '').rpartition('#')
    return int(number) if number.isdigit() else 1


def mission_file_name(landmark_file, when=None):
    """The time-stamped file a mission started at ``when`` records into."""
    when = when or datetime.datetime.now()
    stem, ext = os.path.splitext(landmark_file)
    return '%s-%s%s' % (stem, when.strftime('%Y%m%d-%H%M%S'), ext or '.yaml')


def inspect_landmark_file(landmark_file):
    """What the configured ``landmark_file`` name is: ``'missing'``, ``'regular'``
    (an old layout's file), ``'symlink'`` (to a regular file) or ``'dangling'``
    (a symlink to nothing). Anything else (a directory, a FIFO, a symlink to a
    directory or a loop) raises LandmarkFileError naming it."""
    mode = _mode(os.lstat, landmark_file, 'cannot inspect: %s')
    if mode is None:
        return 'missing'
    if stat.S_ISREG(mode):
        return 'regular'
    if not stat.S_ISLNK(mode):
        raise LandmarkFileError(landmark_file, 'is %s, not a regular file or a symlink to one; '
                                'refusing to use it (move it away or set another landmark_file)'
                                % describe_mode(mode))
    target_mode = _mode(os.stat, landmark_file,
                        'is a symlink that cannot be followed: %s; refusing to use it')
    if target_mode is None:
        return 'dangling'
    if not stat.S_ISREG(target_mode):
        raise LandmarkFileError(landmark_file, 'is a symlink to %s (%s), not to a regular file; '
                                'refusing to use it' % (describe_mode(target_mode),
                                                        os.path.realpath(landmark_file)))
    return 'symlink'


def _mode(stat_call, landmark_file, problem):
    """``stat_call(landmark_file).st_mode``, None if nothing is there; another error
    raises LandmarkFileError with ``problem`` % its text."""
    try:
        return stat_call(landmark_file).st_mode
    except FileNotFoundError:
        return None
    except OSError as error:
        raise LandmarkFileError(landmark_file, problem % (error.strerror or error))


def start_mission_file(landmark_file, when=None):
    """Choose a new file for a mission and point ``landmark_file`` at it.

    Returns the new (not yet created) path. An existing regular file at
    ``landmark_file`` is kept by renaming it to a time-stamped name first; an
    existing symlink is replaced atomically (core/files.replace_with_symlink). Anything else at
    ``landmark_file`` is refused (:func:`inspect_landmark_file`). Nothing
    recorded is deleted. :func:`open_mission_file` creates the file before it
    points the symlink at it.
    """
    target = _new_target(landmark_file, when)
    _point_at(landmark_file, target)
    return target


def _new_target(landmark_file, when):
    """The unused time-stamped name of a new mission file (``landmark_file`` inspected)."""
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    os.makedirs(os.path.dirname(landmark_file), exist_ok=True)
    inspect_landmark_file(landmark_file)
    return _unused(mission_file_name(landmark_file, when))


def _point_at(landmark_file, target):
    """``landmark_file`` a symlink to ``target`` (an old layout's regular file there archived)."""
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    if inspect_landmark_file(landmark_file) == 'regular':
        mtime = datetime.datetime.fromtimestamp(os.path.getmtime(landmark_file))
        os.rename(landmark_file, _unused(mission_file_name(landmark_file, mtime)))
    replace_with_symlink(landmark_file, os.path.basename(target))


def read_mission(path):
    """The ``mission`` id in the header of the landmark file ``path``, or None
    (no header, no id, or not readable: then it is not the current mission)."""
    try:
        text = read_regular_file(path, MAX_FILE_BYTES).decode('utf-8')
    except (OSError, UnicodeDecodeError):
        return None
    for line in text.splitlines():
        if line.startswith(METADATA_KEY + ':'):
            try:
                header = (parse(line) or {}).get(METADATA_KEY)
            except yaml.YAMLError:
                return None
            mission = header.get('mission') if isinstance(header, dict) else None
            return mission if isinstance(mission, str) else None
        if line.startswith(OWN_LINES):
            return None
    return None


def open_mission_file(landmark_file, mission=None, metadata=None, fsync=True, limits=Limits(),
                      when=None):
    """The :class:`LandmarkWriter` of the current mission.

    Rule: if ``mission`` (a non-empty id of the current mission, the same for
    every node restart within it and new for each mission, e.g. the launch's
    start time) is given, and ``landmark_file`` is a symlink to a file whose
    header carries that same ``mission``, the recorder restarted mid-mission:
    that file is continued (:meth:`LandmarkWriter.resume`: validated, a torn
    last entry cut off, labels continued, a gap entry pending; a finished
    recording is not appended to). Otherwise a new file is started with
    ``metadata`` and ``mission`` in its header, and only once it holds its
    header is ``landmark_file`` pointed at it (:func:`start_mission_file`'s
    rules): a storage that cannot hold a file leaves ``landmark_file`` as it
    was, never a symlink to nothing. Without a ``mission`` id a file is never
    continued: appending a new mission to an old one would send the return
    along the old path.

    Raises LandmarkFileError (a ``landmark_file`` that is not a regular file or
    a symlink to one; the current mission's file is corrupt) or StorageError.
    """
    if mission is not None and not (isinstance(mission, str) and mission.strip()):
        raise ValueError('mission must be a non-empty string or None, got %r' % (mission,))
    landmark_file = os.path.abspath(os.path.expanduser(landmark_file))
    if inspect_landmark_file(landmark_file) == 'symlink' and mission is not None:
        target = os.path.realpath(landmark_file)
        if read_mission(target) == mission:
            return LandmarkWriter.resume(target, fsync, limits, reason=RESTART_GAP)
    header = dict(metadata or {})
    if mission is not None:
        header['mission'] = mission
    writer = LandmarkWriter(_new_target(landmark_file, when), header, fsync)
    try:
        _point_at(landmark_file, writer.path)
    except OSError as error:
        writer.close()
        _remove(writer.path)
        raise StorageError(landmark_file, error, 'make a symlink to %s at'
                           % os.path.basename(writer.path))
    return writer


def _remove(path):
    try:
        os.unlink(path)
    except OSError:
        pass


def _unused(path):
    """``path``, or ``path`` with a -N suffix if that name is already taken."""
    stem, ext = os.path.splitext(path)
    candidate, n = path, 1
    while os.path.lexists(candidate):
        candidate = '%s-%d%s' % (stem, n, ext)
        n += 1
    return candidate

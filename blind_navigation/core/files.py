"""Safe file primitives: atomic replacement (a crash leaves the old or the new content, a
planted file is never written through), reading regular files only, and the errors
naming the file (:class:`StorageError`, :class:`FileContentError`)."""
import errno
import os
import secrets
import stat

#: Attempts at a free random temporary name (a 64-bit name already taken: in practice never).
TEMPORARY_ATTEMPTS = 16


class StorageError(OSError):
    """Writing ``path`` failed (``action``, errno, its text; ``lost`` records so far): one line."""

    def __init__(self, path, error, action='write', lost=0):
        code = getattr(error, 'errno', None)
        text = getattr(error, 'strerror', None) or str(error)
        super(StorageError, self).__init__(code, text)
        self.filename = self.path = path
        self.action, self.lost = action, lost
        name = errno.errorcode.get(code) if code else None
        self.message = 'cannot %s %s: %s%s' % (action, path, text, ' (%s)' % name if name else '')
        if lost:
            self.message += '; %d %s lost' % (lost, 'record' if lost == 1 else 'records')

    def __str__(self):
        return self.message


class FileContentError(Exception):
    """A file whose content cannot be used: names the file, the ``part`` (or None), the ``reason``."""

    def __init__(self, path, part, reason):
        self.path, self.part, self.reason = path, part, reason
        where = '%s: %s' % (path, part) if part else str(path)
        super(FileContentError, self).__init__('%s: %s' % (where, reason))


class NotRegularFileError(OSError):
    """``path`` exists but is not a regular file (or a symlink to one): ``what`` it is."""

    def __init__(self, path, what):
        super(NotRegularFileError, self).__init__(errno.EINVAL, 'is %s, not a regular file' % what,
                                                  path)
        self.what = what


def describe_mode(mode):
    """'a directory', 'a FIFO', ... for an ``st_mode``."""
    for test, what in ((stat.S_ISDIR, 'a directory'), (stat.S_ISLNK, 'a symlink'),
                       (stat.S_ISFIFO, 'a FIFO'), (stat.S_ISSOCK, 'a socket'),
                       (stat.S_ISCHR, 'a character device'), (stat.S_ISBLK, 'a block device'),
                       (stat.S_ISREG, 'a regular file')):
        if test(mode):
            return what
    return 'an unknown kind of file'


def write_all(fd, data):
    """Write every byte of ``data`` to ``fd`` (os.write may write fewer)."""
    view = memoryview(data)
    while view:
        written = os.write(fd, view)
        if written <= 0:
            raise OSError(errno.EIO, 'write returned %d' % written)
        view = view[written:]


def fsync_directory(directory):
    """fsync ``directory`` so a rename or a new file in it survives a crash (best effort)."""
    try:
        fd = os.open(directory, os.O_RDONLY | getattr(os, 'O_DIRECTORY', 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _free_name(make, shown):
    """``make(token)`` for the first random token whose name is free (FileExistsError: taken)."""
    for _ in range(TEMPORARY_ATTEMPTS):
        try:
            return make(secrets.token_hex(8))
        except FileExistsError:
            continue
    raise FileExistsError(errno.EEXIST, 'no free temporary name after %d attempts'
                          % TEMPORARY_ATTEMPTS, shown)


def replace_with_symlink(path, target):
    """Make ``path`` a symlink to ``target`` atomically (made beside it, renamed over it)."""
    directory, name = os.path.split(os.path.abspath(path))

    def make(token):
        link = os.path.join(directory, '.%s.%s.link' % (name, token))
        os.symlink(target, link)
        return link
    link = _free_name(make, path)
    try:
        os.replace(link, path)
    except OSError:
        os.unlink(link)
        raise
    fsync_directory(directory)


def remove_quietly(path):
    """Remove ``path`` if it can be (best effort)."""
    try:
        os.unlink(path)
    except OSError:
        pass


def write_atomically(path, text):
    """Replace ``path`` by ``text`` atomically; StorageError naming it on failure (old content kept)."""
    path = os.path.abspath(path)
    directory, name = os.path.split(path)
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | getattr(os, 'O_CLOEXEC', 0)
    temporary = None

    def create(token):      # a new file: never an existing one, never through a symlink
        created = os.path.join(directory, '.%s.%s.tmp' % (name, token))
        return os.open(created, flags, 0o666), created
    try:
        if os.path.isdir(path) and not os.path.islink(path):
            raise IsADirectoryError(errno.EISDIR, 'is a directory', path)
        fd, temporary = _free_name(create, os.path.join(directory, '.%s.*.tmp' % name))
        try:
            write_all(fd, text.encode('utf-8'))
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(temporary, path)     # replaces a symlink itself, never its target
        temporary = None
        fsync_directory(directory)
    except OSError as error:
        raise StorageError(path, error)
    finally:
        if temporary is not None:
            remove_quietly(temporary)


def read_regular_file(path, max_bytes, follow_symlinks=True):
    """The bytes of the regular file ``path`` (at most ``max_bytes``), else an OSError naming it."""
    flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, 'O_CLOEXEC', 0)
    if not follow_symlinks:
        flags |= os.O_NOFOLLOW
    try:
        fd = os.open(path, flags)
    except OSError as error:
        if error.errno == errno.ELOOP and not follow_symlinks:
            raise NotRegularFileError(path, 'a symlink')
        raise
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise NotRegularFileError(path, describe_mode(info.st_mode))
        if info.st_size > max_bytes:
            raise OSError(errno.EFBIG, 'larger than %d bytes (%d)' % (max_bytes, info.st_size), path)
        chunks, size = [], 0
        while True:
            chunk = os.read(fd, 1 << 16)
            if not chunk:
                break
            size += len(chunk)
            if size > max_bytes:
                raise OSError(errno.EFBIG, 'larger than %d bytes' % max_bytes, path)
            chunks.append(chunk)
        return b''.join(chunks)
    finally:
        os.close(fd)

"""Unit tests of core/files.py: atomic replacement that never follows a planted
symlink, one clear StorageError for a failed write (also on a really full
file system: the tiny_tmpfs fixture of conftest.py), and reading only regular files."""
import errno
import os

import pytest

from blind_navigation.core import files
from blind_navigation.core.files import (NotRegularFileError, StorageError, read_regular_file,
                                         replace_with_symlink, write_atomically)


def test_write_atomically_replaces_and_leaves_no_temporary(tmp_path):
    path = str(tmp_path / 'calibration.yaml')
    write_atomically(path, 'a: 1\n')
    write_atomically(path, 'a: 2\n')
    assert open(path).read() == 'a: 2\n'
    assert os.listdir(str(tmp_path)) == ['calibration.yaml']


def test_a_symlink_planted_at_the_chosen_temporary_name_is_never_opened(tmp_path, monkeypatch):
    victim = tmp_path / 'victim'
    victim.write_text('precious\n')
    names = iter(['planted', 'planted', 'free'])
    monkeypatch.setattr(files.secrets, 'token_hex', lambda n: next(names))
    os.symlink(str(victim), str(tmp_path / '.p.yaml.planted.tmp'))
    write_atomically(str(tmp_path / 'p.yaml'), 'new\n')
    assert victim.read_text() == 'precious\n'
    assert (tmp_path / 'p.yaml').read_text() == 'new\n'
    assert os.path.islink(str(tmp_path / '.p.yaml.planted.tmp'))


def test_a_symlink_at_the_target_is_replaced_not_written_through(tmp_path):
    victim = tmp_path / 'victim'
    victim.write_text('precious\n')
    target = tmp_path / 'p.yaml'
    os.symlink(str(victim), str(target))
    write_atomically(str(target), 'new\n')
    assert victim.read_text() == 'precious\n'
    assert not os.path.islink(str(target)) and target.read_text() == 'new\n'


def test_a_directory_at_the_target_is_a_storage_error(tmp_path):
    (tmp_path / 'p.yaml').mkdir()
    with pytest.raises(StorageError) as error:
        write_atomically(str(tmp_path / 'p.yaml'), 'x')
    assert 'p.yaml' in str(error.value) and 'directory' in str(error.value)
    assert sorted(os.listdir(str(tmp_path))) == ['p.yaml']


@pytest.mark.parametrize('code', [errno.ENOSPC, errno.EIO, errno.EACCES])
def test_write_failures_are_one_clear_error(tmp_path, monkeypatch, code):
    path = str(tmp_path / 'p.yaml')
    write_atomically(path, 'old\n')

    def failing_write(fd, data):
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(os, 'write', failing_write)
    with pytest.raises(StorageError) as error:
        write_atomically(path, 'new\n')
    monkeypatch.undo()
    message = str(error.value)
    assert message == 'cannot write %s: %s (%s)' % (path, os.strerror(code), errno.errorcode[code])
    assert isinstance(error.value, OSError) and error.value.errno == code
    assert open(path).read() == 'old\n' and os.listdir(str(tmp_path)) == ['p.yaml']


def test_replace_with_symlink(tmp_path):
    link = str(tmp_path / 'landmarks.yaml')
    replace_with_symlink(link, 'a.yaml')
    replace_with_symlink(link, 'b.yaml')
    assert os.readlink(link) == 'b.yaml' and os.listdir(str(tmp_path)) == ['landmarks.yaml']


def test_read_regular_file_refuses_what_is_not_one(tmp_path):
    regular = tmp_path / 'f'
    regular.write_bytes(b'12345')
    assert read_regular_file(str(regular), 5) == b'12345'
    with pytest.raises(OSError, match='larger than 4 bytes'):
        read_regular_file(str(regular), 4)
    os.symlink('f', str(tmp_path / 'link'))
    assert read_regular_file(str(tmp_path / 'link'), 5) == b'12345'
    with pytest.raises(NotRegularFileError, match='a symlink'):
        read_regular_file(str(tmp_path / 'link'), 5, follow_symlinks=False)
    os.mkfifo(str(tmp_path / 'fifo'))                   # would block a plain open()
    with pytest.raises(NotRegularFileError, match='a FIFO'):
        read_regular_file(str(tmp_path / 'fifo'), 5)
    with pytest.raises(NotRegularFileError, match='a directory'):
        read_regular_file(str(tmp_path), 5)
    with pytest.raises(FileNotFoundError):
        read_regular_file(str(tmp_path / 'none'), 5)


def test_a_really_full_file_system(tiny_tmpfs):
    path = str(tiny_tmpfs / 'progress.yaml')
    write_atomically(path, 'small\n')
    with pytest.raises(StorageError) as error:
        write_atomically(path, 'x' * (128 << 10))
    assert 'No space left on device (ENOSPC)' in str(error.value) and path in str(error.value)
    assert open(path).read() == 'small\n' and os.listdir(str(tiny_tmpfs)) == ['progress.yaml']

"""Make the repo's Python package importable for unit tests run without catkin;
shared fixtures; with ``CI`` set, hypothesis runs derandomized (docs/testing.md)."""
import os
import subprocess
import sys

import pytest
from hypothesis import settings

sys.path.insert(0, os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))

# CI: the same examples on every run (a clean clone has no example database to replay)
settings.register_profile('ci', derandomize=True, database=None)
if os.environ.get('CI'):
    settings.load_profile('ci')


@pytest.fixture
def tiny_tmpfs(tmp_path):
    """A 64 KiB tmpfs (needs root and mount rights; skipped otherwise)."""
    mount_point = tmp_path / 'tiny'
    mount_point.mkdir()
    if os.geteuid() != 0:
        pytest.skip('mounting a tmpfs needs root')
    result = subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=64k', 'tmpfs', str(mount_point)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=10)
    if result.returncode != 0:
        pytest.skip('cannot mount a tmpfs here: %s' % result.stdout.decode().strip())
    try:
        yield mount_point
    finally:
        subprocess.run(['umount', str(mount_point)], timeout=10, check=True)

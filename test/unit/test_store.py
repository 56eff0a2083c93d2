"""The YAML landmark store: format, round trips, torn entries, bad files."""
import math
import os

import pytest
import yaml

from blind_navigation.core.landmark import Landmark, landmark_from_values
from blind_navigation.core.store import (LandmarkFileError, LandmarkWriter, format_entry,
                                         load_landmarks, start_mission_file)

PATH = [Landmark(0.0861, 0.0012, 0.1718, 2.0, 0.0131),
        Landmark(0.0859, 0.0964, 0.0862, 1.0, 0.0610),
        Landmark(0.09, -0.097, 0.09, 1.0, -3.1),
        Landmark(1e-5, -2.5e-7, 0.0, 2.0, -3.14159)]


def write(path, landmarks=PATH, **kwargs):
    with LandmarkWriter(str(path), **kwargs) as writer:
        for landmark in landmarks:
            writer.append(landmark)
    return writer


def test_round_trip(tmp_path):
    path = tmp_path / 'lm.yaml'
    writer = write(path, metadata={'odom_topic': '/odom'})
    loaded = load_landmarks(str(path))
    assert loaded.landmarks == PATH
    assert loaded.labels == ['landmark_%06d' % i for i in range(1, 5)]
    assert loaded.metadata['odom_topic'] == '/odom'
    assert loaded.warnings == []
    assert writer.count == 4
    assert loaded.total_distance == pytest.approx(sum(l.d for l in PATH))


def test_numbers_keep_six_significant_digits(tmp_path):
    path = tmp_path / 'lm.yaml'
    exact = Landmark(0.0861234567, -0.0964123456, 13.2345678, 2.0, math.pi)
    write(path, [exact])
    stored = load_landmarks(str(path)).landmarks[0]
    for kept, original in zip(stored, exact):
        assert kept == pytest.approx(original, rel=5e-6, abs=1e-12)  # half a unit in the 6th digit


def test_file_is_plain_yaml_in_the_interface_format(tmp_path):
    path = tmp_path / 'lm.yaml'
    write(path, fsync=False)
    document = yaml.safe_load(path.read_text())
    assert document['landmark_000001'] == {'data': [0.0861, 0.0012, 0.1718, 2.0, 0.0131]}
    lines = [l for l in path.read_text().splitlines() if l.startswith('landmark_')]
    assert lines[0] == 'landmark_000001: {data: [0.0861, 0.0012, 0.1718, 2.0, 0.0131]}'
    assert all(not key.startswith('landmark_') or set(value) == {'data'}
               for key, value in document.items())


def test_writer_never_overwrites(tmp_path):
    path = tmp_path / 'lm.yaml'
    write(path)
    with pytest.raises(FileExistsError):
        LandmarkWriter(str(path))
    assert load_landmarks(str(path)).landmarks == PATH


def test_torn_last_entry_is_dropped_and_reported(tmp_path):
    path = tmp_path / 'lm.yaml'
    write(path)
    with open(str(path), 'a') as stream:
        stream.write(format_entry('landmark_000005', PATH[0])[:25])   # killed mid-write
    loaded = load_landmarks(str(path))
    assert loaded.landmarks == PATH
    assert len(loaded.warnings) == 1 and 'torn' in loaded.warnings[0]


def test_start_mission_file_keeps_earlier_missions(tmp_path):
    link = str(tmp_path / 'dir' / 'landmarks.yaml')
    first = start_mission_file(link)
    write(first)
    second = start_mission_file(link)
    assert first != second and not os.path.exists(second)
    write(second, PATH[:1])
    assert load_landmarks(link).landmarks == PATH[:1]
    assert load_landmarks(first).landmarks == PATH


def test_start_mission_file_archives_a_regular_file(tmp_path):
    link = tmp_path / 'landmarks.yaml'
    write(link)
    target = start_mission_file(str(link))
    archived = [p for p in tmp_path.iterdir() if p.name.startswith('landmarks-')]
    assert len(archived) == 1 and load_landmarks(str(archived[0])).landmarks == PATH
    assert os.path.realpath(str(link)) == target


BAD_FILES = {
    'empty': ('', 'no landmarks'),
    'not yaml': ('landmark_000001: {data: [1, 2\n  - : ]]\n', 'not valid YAML'),
    'not a map': ('- 1\n- 2\n', 'top level must be a map'),
    'wrong type': ('landmark_000001: {data: [0.1, 0.0, x, 1.0, 0.0]}\n', 'd is not a number'),
    'nan': ('landmark_000001: {data: [.nan, 0.0, 0.1, 1.0, 0.0]}\n', 'v is not finite'),
    'inf': ('landmark_000001: {data: [0.1, .inf, 0.1, 1.0, 0.0]}\n', 'w is not finite'),
    'negative d': ('landmark_000001: {data: [0.1, 0.0, -0.1, 1.0, 0.0]}\n', 'd is negative'),
    'zero T': ('landmark_000001: {data: [0.1, 0.0, 0.1, 0.0, 0.0]}\n', 'T must be positive'),
    'too fast': ('landmark_000001: {data: [2.0, 0.0, 0.1, 1.0, 0.0]}\n', 'exceeds the limit'),
    'four values': ('landmark_000001: {data: [0.1, 0.0, 0.1, 1.0]}\n', 'five numbers'),
    'no data': ('landmark_000001: [0.1, 0.0, 0.1, 1.0, 0.0]\n', 'data sequence'),
    'duplicate': ('landmark_000001: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n'
                  'landmark_000001: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n', 'duplicate key'),
    'out of order': ('landmark_000002: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n'
                     'landmark_000001: {data: [0.1, 0.0, 0.1, 1.0, 0.0]}\n', 'out of recording order'),
}


@pytest.mark.parametrize('name', sorted(BAD_FILES))
def test_bad_file_is_refused_naming_file_and_entry(tmp_path, name):
    text, reason = BAD_FILES[name]
    path = tmp_path / 'bad.yaml'
    path.write_text(text)
    with pytest.raises(LandmarkFileError) as error:
        load_landmarks(str(path))
    message = str(error.value)
    assert str(path) in message and reason in message, message
    if 'landmark_000001: {data' in text and name not in ('duplicate', 'out of order', 'not yaml'):
        assert 'landmark_000001' in message


def test_missing_file_is_refused(tmp_path):
    with pytest.raises(LandmarkFileError) as error:
        load_landmarks(str(tmp_path / 'nope.yaml'))
    assert 'cannot read' in str(error.value)


def test_landmark_rejects_booleans_and_bad_psi():
    with pytest.raises(ValueError):
        landmark_from_values([True, 0.0, 0.1, 1.0, 0.0])
    with pytest.raises(ValueError):
        landmark_from_values([0.1, 0.0, 0.1, 1.0, 4.0])

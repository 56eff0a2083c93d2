"""The landmark file's format: its keys, lines and numbers, and its strict YAML.

One flow-map line per entry (INTERFACE.md; PyYAML and yaml-cpp read it): the
``blind_navigation`` header, ``landmark_NNNNNN: {data: [v, w, d, T, psi]}``, ``gap_<n>``
and ``samples_<n>`` marks, a ``finished`` line. Reader: core/store.py; writer:
core/landmark_writer.py; mission files: core/mission_files.py (docs/recording.md, "File").
"""
import re
from collections import namedtuple

import yaml

from .files import FileContentError

LABEL_PREFIX = 'landmark_'
LABEL_RE = re.compile(r'^landmark_(\d+)$')
GAP_RE = re.compile(r'^gap_(\d+)$')
SAMPLES_RE = re.compile(r'^samples_(\d+)$')
METADATA_KEY = 'blind_navigation'
FINISHED_KEY = 'finished'
FORMAT_VERSION = 1
#: Largest landmark file read (about 300 hours of recording at 1 landmark/s).
MAX_FILE_BYTES = 64 << 20
#: Kinds of entry line the writer makes (a torn one is dropped on load).
OWN_LINES = (LABEL_PREFIX, 'gap_', 'samples_', FINISHED_KEY + ':')


class LandmarkFileError(FileContentError):
    """A landmark file that cannot be used; the message names the file and entry."""

    def __init__(self, path, reason, entry=None):
        super(LandmarkFileError, self).__init__(path, entry, reason)
        self.entry = entry


def label_for(index):
    """The unique, ordered key of the ``index``-th landmark (1-based)."""
    return '%s%06d' % (LABEL_PREFIX, index)


def format_number(value):
    """Compact text for one float (six significant digits) that YAML 1.1 reads as
    a float: PyYAML needs a '.' in the mantissa ('1e-05' would be a string)."""
    mantissa, e, exponent = ('%.6g' % value).partition('e')
    if '.' not in mantissa:
        mantissa += '.0'
    return mantissa + e + exponent


def format_entry(label, landmark):
    """One line of the store for ``landmark`` under ``label``."""
    return '%s: {data: [%s]}\n' % (label, ', '.join(format_number(v) for v in landmark))


def flow_line(key, value):
    """``key: {...}`` on one line (YAML flow style)."""
    return '%s: %s' % (key, yaml.safe_dump(value, default_flow_style=True, width=1 << 30))


Gap = namedtuple('Gap', 'before reason')
Gap.__doc__ = ('A break in the d chain: ``before`` is the label of the first landmark after it '
               '(its d does not start at the previous landmark), ``reason`` says why.')

SampleMark = namedtuple('SampleMark', 'recording seq')
SampleMark.__doc__ = ('A sample of the sampling publisher: its ``recording`` (the time the recording '
                      'started, s) and its number ``seq`` in it (1, 2, ...).')


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses duplicate keys instead of keeping the last one."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, 'duplicate key %r' % (key,), key_node.start_mark)
            seen.add(key)
        return super(_UniqueKeyLoader, self).construct_mapping(node, deep)


def parse(text):
    return yaml.load(text, Loader=_UniqueKeyLoader)


def drop_torn_tail(path, text, warnings):
    """``text`` without a torn last entry (a killed writer's partial line)."""
    if text and not text.endswith('\n'):
        cut = text.rfind('\n') + 1
        warnings.append('%s: dropped a torn last entry (no end of line): %r' % (path, text[cut:][:80]))
        return text[:cut]
    lines = text.splitlines(True)
    if lines and lines[-1].startswith(OWN_LINES):
        try:
            parse(lines[-1])
        except yaml.YAMLError:
            warnings.append('%s: dropped an unparsable last entry: %r' % (path, lines[-1][:80]))
            return ''.join(lines[:-1])
    return text

"""Refuses wrong wiring: :class:`Expected` is what a topic must carry, checked on each
connection's first message and at the master; a mismatch (:func:`refuse`): one FATAL line,
the messages dropped, a fault declared (docs/safety.md, "Bad input").
"""
import rospy

from blind_navigation.core import outcome

from . import faults


class Expected(object):
    """A topic must carry one of ``types`` (``pkg/Name``), with ``md5sum`` if given."""

    def __init__(self, types, md5sum=None):
        self.types = tuple(types)
        self.md5sum = md5sum
        self._accepted = None       # the last connection header accepted (identity)

    @classmethod
    def of(cls, data_class):
        """The type and MD5 sum of a message class."""
        return cls((data_class._type,), data_class._md5sum)

    def __str__(self):
        return ' or '.join(self.types)

    def mismatch(self, found_type, found_md5=None):
        """None when ``found_type`` (and ``found_md5``, unless None or ``*``) is expected, else what."""
        if found_type not in self.types:
            return found_type or 'a message without a type'
        if self.md5sum and found_md5 not in (None, '*', self.md5sum):
            return '%s with MD5 sum %s (another version: %s expected)' % (found_type, found_md5,
                                                                           self.md5sum)
        return None

    def accepts(self, topic, header):
        """True if the connection ``header`` carries this type; else refused and False."""
        if header is self._accepted:
            return True
        found = self.mismatch(header.get('type'), header.get('md5sum'))
        if found is None:
            self._accepted = header
            return True
        refuse(topic, self, found)
        return False


def refuse(topic, expected, found):
    """``topic`` carries ``found``, not ``expected``: declared, then one FATAL line per topic."""
    topic = rospy.resolve_name(topic)
    fault = 'wrong wiring: %s carries %s, expected %s' % (topic, found, expected)
    if faults.declare(topic, fault, outcome.WIRING):    # once per topic: the outputs stopped, the owner told
        rospy.logfatal('%s: %s: refused, nothing moves (fix the remap and start the layer again)',
                       rospy.get_name(), fault)


def check_types(topic_types, expected_by_topic):
    """Refuse each topic of ``expected_by_topic`` whose type in ``topic_types`` (the master's) differs."""
    types = dict(topic_types)
    for topic, expected in expected_by_topic.items():
        found = types.get(topic)
        if found is not None and expected.mismatch(found) is not None:
            refuse(topic, expected, expected.mismatch(found))


"""Kobuki's message types (kobuki_msgs) without a build dependency on kobuki_msgs.

The installed package's classes when there are any, else identical classes (same type
names and MD5 sums) generated at import from the same definitions.
"""
import genpy.dynamic

DEFINITIONS = {
    'BumperEvent': 'uint8 LEFT=0\nuint8 CENTER=1\nuint8 RIGHT=2\n'
                   'uint8 RELEASED=0\nuint8 PRESSED=1\nuint8 bumper\nuint8 state\n',
    'CliffEvent': 'uint8 LEFT=0\nuint8 CENTER=1\nuint8 RIGHT=2\n'
                  'uint8 FLOOR=0\nuint8 CLIFF=1\nuint8 sensor\nuint8 state\nuint16 bottom\n',
    'WheelDropEvent': 'uint8 LEFT=0\nuint8 RIGHT=1\nuint8 RAISED=0\nuint8 DROPPED=1\n'
                      'uint8 wheel\nuint8 state\n',
    'MotorPower': 'uint8 OFF=0\nuint8 ON=1\nuint8 state\n',
}


def _load():
    try:
        import kobuki_msgs.msg as real
        return {name: getattr(real, name) for name in DEFINITIONS}
    except (ImportError, AttributeError):    # AttributeError: a kobuki_msgs without its classes
        return {name: genpy.dynamic.generate_dynamic('kobuki_msgs/' + name, text)['kobuki_msgs/' + name]
                for name, text in DEFINITIONS.items()}


_CLASSES = _load()
BumperEvent = _CLASSES['BumperEvent']
CliffEvent = _CLASSES['CliffEvent']
WheelDropEvent = _CLASSES['WheelDropEvent']
MotorPower = _CLASSES['MotorPower']

#: Kobuki sensor names (sim/arena.py) -> message index constants.
BUMPER_INDEX = {'left': 0, 'center': 1, 'right': 2}
CLIFF_INDEX = {'left': 0, 'center': 1, 'right': 2}
WHEEL_INDEX = {'left': 0, 'right': 1}

"""Kobuki's message types (kobuki_msgs) without a build dependency on kobuki_msgs.

The installed package's classes when there are any, else identical classes (same type
names and MD5 sums) generated at import from the same definitions.
"""
import genpy.dynamic

#: std_msgs/Header as a message definition's dependency (genpy.dynamic's format)
HEADER = ('=' * 80 + '\nMSG: std_msgs/Header\n'
          'uint32 seq\ntime stamp\nstring frame_id\n')

DEFINITIONS = {
    'BumperEvent': 'uint8 LEFT=0\nuint8 CENTER=1\nuint8 RIGHT=2\n'
                   'uint8 RELEASED=0\nuint8 PRESSED=1\nuint8 bumper\nuint8 state\n',
    'CliffEvent': 'uint8 LEFT=0\nuint8 CENTER=1\nuint8 RIGHT=2\n'
                  'uint8 FLOOR=0\nuint8 CLIFF=1\nuint8 sensor\nuint8 state\nuint16 bottom\n',
    'WheelDropEvent': 'uint8 LEFT=0\nuint8 RIGHT=1\nuint8 RAISED=0\nuint8 DROPPED=1\n'
                      'uint8 wheel\nuint8 state\n',
    'MotorPower': 'uint8 OFF=0\nuint8 ON=1\nuint8 state\n',
    # kobuki_msgs 0.7.0 (Noetic's): the core sensors at 50 Hz, battery in 0.1 V
    'SensorState': 'uint8 BUMPER_RIGHT=1\nuint8 BUMPER_CENTRE=2\nuint8 BUMPER_LEFT=4\n'
                   'uint8 WHEEL_DROP_RIGHT=1\nuint8 WHEEL_DROP_LEFT=2\n'
                   'uint8 CLIFF_RIGHT=1\nuint8 CLIFF_CENTRE=2\nuint8 CLIFF_LEFT=4\n'
                   'uint8 BUTTON0=1\nuint8 BUTTON1=2\nuint8 BUTTON2=4\n'
                   'uint8 DISCHARGING=0\nuint8 DOCKING_CHARGED=2\nuint8 DOCKING_CHARGING=6\n'
                   'uint8 ADAPTER_CHARGED=18\nuint8 ADAPTER_CHARGING=22\n'
                   'uint8 OVER_CURRENT_LEFT_WHEEL=1\nuint8 OVER_CURRENT_RIGHT_WHEEL=2\n'
                   'uint8 OVER_CURRENT_BOTH_WHEELS=3\n'
                   'uint8 DIGITAL_INPUT0=1\nuint8 DIGITAL_INPUT1=2\nuint8 DIGITAL_INPUT2=4\n'
                   'uint8 DIGITAL_INPUT3=8\nuint8 DB25_TEST_BOARD_CONNECTED=64\n'
                   'Header header\nuint16 time_stamp\nuint8 bumper\nuint8 wheel_drop\nuint8 cliff\n'
                   'uint16 left_encoder\nuint16 right_encoder\nint8 left_pwm\nint8 right_pwm\n'
                   'uint8 buttons\nuint8 charger\nuint8 battery\nuint16[] bottom\nuint8[] current\n'
                   'uint8 over_current\nuint16 digital_input\nuint16[] analog_input\n' + HEADER,
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
SensorState = _CLASSES['SensorState']

#: Kobuki sensor names (sim/arena.py) -> message index constants.
BUMPER_INDEX = {'left': 0, 'center': 1, 'right': 2}
CLIFF_INDEX = {'left': 0, 'center': 1, 'right': 2}
WHEEL_INDEX = {'left': 0, 'right': 1}

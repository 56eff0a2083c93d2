"""Kobuki's message types (kobuki_msgs) without a build dependency on kobuki_msgs: the
installed package's classes, else identical ones (same names and MD5 sums) generated at import."""
import genpy.dynamic
from actionlib_msgs.msg import GoalID, GoalStatus
from std_msgs.msg import Header

DEFINITIONS = {
    'BumperEvent': 'uint8 LEFT=0\nuint8 CENTER=1\nuint8 RIGHT=2\n'
                   'uint8 RELEASED=0\nuint8 PRESSED=1\nuint8 bumper\nuint8 state\n',
    'CliffEvent': 'uint8 LEFT=0\nuint8 CENTER=1\nuint8 RIGHT=2\n'
                  'uint8 FLOOR=0\nuint8 CLIFF=1\nuint8 sensor\nuint8 state\nuint16 bottom\n',
    'WheelDropEvent': 'uint8 LEFT=0\nuint8 RIGHT=1\nuint8 RAISED=0\nuint8 DROPPED=1\n'
                      'uint8 wheel\nuint8 state\n',
    'MotorPower': 'uint8 OFF=0\nuint8 ON=1\nuint8 state\n',
    'DockInfraRed': 'uint8 NEAR_LEFT=1\nuint8 NEAR_CENTER=2\nuint8 NEAR_RIGHT=4\nuint8 FAR_LEFT=16\n'
                    'uint8 FAR_CENTER=8\nuint8 FAR_RIGHT=32\nHeader header\nuint8[] data\n',
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
                   'uint8 over_current\nuint16 digital_input\nuint16[] analog_input\n',
}
#: kobuki_msgs/AutoDocking.action as genaction expands it (goal empty, result text, feedback state, text).
ACTION_DEFINITIONS = {
    'AutoDockingAction': 'AutoDockingActionGoal action_goal\nAutoDockingActionResult action_result\n'
                         'AutoDockingActionFeedback action_feedback\n',
    'AutoDockingActionGoal': 'Header header\nactionlib_msgs/GoalID goal_id\nAutoDockingGoal goal\n',
    'AutoDockingActionResult': 'Header header\nactionlib_msgs/GoalStatus status\nAutoDockingResult result\n',
    'AutoDockingActionFeedback': 'Header header\nactionlib_msgs/GoalStatus status\n'
                                 'AutoDockingFeedback feedback\n',
    'AutoDockingGoal': '',
    'AutoDockingResult': 'string text\n',
    'AutoDockingFeedback': 'string state\nstring text\n',
}
_SEPARATOR = '\n' + '=' * 80 + '\n'


def _load():
    """The classes, generated from one concatenated definition if kobuki_msgs has none."""
    definitions = dict(ACTION_DEFINITIONS, **DEFINITIONS)     # the action first: the core type
    try:
        import kobuki_msgs.msg as real
        return {name: getattr(real, name) for name in definitions}
    except (ImportError, AttributeError):    # AttributeError: a kobuki_msgs without its classes
        names = list(definitions)
        parts = [definitions[names[0]]] + ['MSG: kobuki_msgs/%s\n%s' % (name, definitions[name])
                                           for name in names[1:]]
        parts += ['MSG: %s\n%s' % (cls._type, cls._full_text.split(_SEPARATOR)[0])
                  for cls in (Header, GoalID, GoalStatus)]
        classes = genpy.dynamic.generate_dynamic('kobuki_msgs/' + names[0], _SEPARATOR.join(parts))
        return {name: classes['kobuki_msgs/' + name] for name in names}


_CLASSES = _load()
(BumperEvent, CliffEvent, WheelDropEvent, MotorPower, DockInfraRed, SensorState, AutoDockingAction,
 AutoDockingGoal, AutoDockingResult, AutoDockingFeedback) = (_CLASSES[name] for name in (
    'BumperEvent', 'CliffEvent', 'WheelDropEvent', 'MotorPower', 'DockInfraRed', 'SensorState',
    'AutoDockingAction', 'AutoDockingGoal', 'AutoDockingResult', 'AutoDockingFeedback'))

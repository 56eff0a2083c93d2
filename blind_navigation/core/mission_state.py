"""The mission's one state machine, obeyed by every role of the layer.

States, published latched on ``blind_navigation/state`` (std_msgs/String) by
the mission's owner (back_travel_client)::

    idle -> recording -> rotating -> returning -> home
                 \\            \\            \\-> aborted
                  \\            \\-> aborted
                   \\-> aborted (idle -> aborted too: a return that cannot resume)

- ``recording``: the recorder saved its first landmark.
- ``rotating``: vision was lost while recording (a trigger in any other state
  is logged and changes nothing; repeated triggers change nothing).
- ``returning``: the pi turn is over and the robot really turned.
- ``home`` / ``aborted``: terminal. Nothing moves until a new mission starts.

Motion is commanded only by the role that owns the phase (:data:`MOTION_OWNER`):
the pi turn in ``rotating``, the back travel in ``returning``; every velocity
output of the layer asks :func:`may_move` before it publishes anything but zero.
"""

IDLE = 'idle'
RECORDING = 'recording'
ROTATING = 'rotating'
RETURNING = 'returning'
HOME = 'home'
ABORTED = 'aborted'

ALL = (IDLE, RECORDING, ROTATING, RETURNING, HOME, ABORTED)
TERMINAL = (HOME, ABORTED)

#: Allowed transitions: state -> the states it may move to.
TRANSITIONS = {
    IDLE: (RECORDING, ABORTED),
    RECORDING: (ROTATING, ABORTED),
    ROTATING: (RETURNING, ABORTED),
    RETURNING: (HOME, ABORTED),
    HOME: (),
    ABORTED: (),
}

#: The role that may command motion in a state (the roles are the layer's node classes).
ROTATION_ROLE = 'rotate_pi'
BACK_TRAVEL_ROLE = 'back_travel_server'
#: The one-off gyro calibration runs outside any mission (no state) and may spin then.
CALIBRATION_ROLE = 'calibrate_gyro'
MOTION_OWNER = {ROTATING: ROTATION_ROLE, RETURNING: BACK_TRAVEL_ROLE}


def may_move(role, state):
    """True when ``role`` may command motion while the mission is in ``state``
    (None: no mission is running, which only the calibration may use)."""
    if state is None:
        return role == CALIBRATION_ROLE
    return MOTION_OWNER.get(state) == role


def records(state):
    """True while the path is recorded (before the first landmark and after it)."""
    return state in (None, IDLE, RECORDING)

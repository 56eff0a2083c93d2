"""Mission states published on /blind_navigation/state (latched std_msgs/String)."""

IDLE = 'idle'
RECORDING = 'recording'
ROTATING = 'rotating'
RETURNING = 'returning'
HOME = 'home'
ABORTED = 'aborted'

ALL = (IDLE, RECORDING, ROTATING, RETURNING, HOME, ABORTED)

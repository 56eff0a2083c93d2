"""The Kobuki battery for the mission owner: ``battery`` of mobile_base/sensors/core
(kobuki_msgs/SensorState, 0.1 V) into its Inbox, where core/battery.py watches it."""
import rospy

from .. import names
from ..core.battery import reading_problem
from . import kobuki_msgs_compat as kobuki
from .common import subscribe_checked

#: s between two warnings about ignored battery readings
WARN_PERIOD = 10.0


def subscribe_battery(threshold, inbox, guard, log):
    """With ``threshold`` (battery_low, V) > 0: each SensorState's battery (V) on
    names.CORE_SENSORS put into ``inbox`` as ``battery``; another type on the topic is
    refused (ros/wiring.py). The subscriber, or None when off."""
    if not threshold > 0:
        return None

    def on_core(msg):
        volts = msg.battery / 10.0
        problem = reading_problem(volts)
        if problem:
            rospy.logwarn_throttle(WARN_PERIOD, '%s: battery reading ignored: %s'
                                   % (rospy.get_name(), problem))
        inbox.put(battery=volts)
    log.info('battery_low %.1f V: a battery below it on %s while recording starts the return',
             threshold, rospy.resolve_name(names.CORE_SENSORS))
    return subscribe_checked(names.CORE_SENSORS, kobuki.SensorState, guard(on_core), queue_size=1)

"""vulture's false positives in the product (scripts/vulture_junit.py): names it
reports unused at 60 % confidence that are used where it cannot see."""
# pylint: disable=undefined-variable,pointless-statement
# ROS handles kept on self so that the timer, subscriber or service stays alive
_.sample_sub        # ros/landmark_saving.py: the sample subscriber
_.manual_sub        # ros/vision_monitor.py: the manual vision_lost subscriber, kept across missions
_.samples_service   # ros/sampling_publisher.py: the RecordedSamples service
# OSError's own attribute (tracebacks and callers read it): core/files.py's errors
_.filename
# Not used yet: the mission state machine (issue 22 item 1) consults it when it lands,
# and then this line goes.
TRANSITIONS

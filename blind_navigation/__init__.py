"""blind_navigation: a way home for a vSLAM robot whose camera failed.

Layers:
- ``blind_navigation.core``: plain Python (no rospy): landmarks, the segment
  classifier, the landmark store, controllers, the simulated Kobuki base.
- ``blind_navigation.nodes``: one ROS node per module, each a class owning its
  publishers, subscribers and ``~private`` params, plus a tiny ``main()``.
"""

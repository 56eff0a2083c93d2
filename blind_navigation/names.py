"""Every topic, service and action name of the layer, relative (a robot's namespace, remaps):
in the root namespace INTERFACE.md's; only ``/clock`` is global."""

# --- the robot's topics the layer reads or drives (TurtleBot2 / Kobuki / RTAB-Map names)
#: nav_msgs/Odometry, wheel(+gyro) odometry: the source that survives vision loss
ODOM = 'odom'
#: geometry_msgs/Twist the pi turn and the back travel drive (a cmd_vel_mux input, as in the paper)
CMD_VEL = 'cmd_vel_mux/input/teleop'
#: std_msgs/String, the mux's active input (its name, or ``idle``): a takeover (ros/motion.TakeoverWatch)
CMD_VEL_MUX_ACTIVE = 'cmd_vel_mux/active'
#: geometry_msgs/Twist the mux forwards to the base: a command the layer did not send is a takeover
MUX_OUTPUT = 'mobile_base/commands/velocity'
#: geometry_msgs/Pose2D, the paper's yaw source (sampling_publisher with yaw_source pose2d)
POSE2D = 'pose2d'
#: sensor_msgs/Image of the RGB camera (vision-loss detection, the dark detector only)
CAMERA = 'camera/rgb/image_rect_color'
#: sensor_msgs/CameraInfo published with every camera frame (the cheap camera-stall signal)
CAMERA_INFO = 'camera/rgb/camera_info'
#: nav_msgs/Odometry of RTAB-Map's visual odometry (heading correction, detection)
VO_ODOM = 'rtabmap/odom'
#: RTAB-Map's OdomInfo without words, keypoints and local map (docs/detection.md)
VO_ODOM_INFO = 'rtabmap/odom_info_lite'
#: Kobuki's safety events (kobuki_msgs/BumperEvent, CliffEvent, WheelDropEvent)
SAFETY_EVENTS = {'bumper': 'mobile_base/events/bumper',
                 'cliff': 'mobile_base/events/cliff',
                 'wheel_drop': 'mobile_base/events/wheel_drop'}
#: kobuki_msgs/SensorState, the Kobuki's core sensors (battery in 0.1 V): read with battery_low
CORE_SENSORS = 'mobile_base/sensors/core'
#: kobuki_msgs/AutoDocking, kobuki_auto_docking's action (it drives MUX_OUTPUT itself): with dock_at_home
DOCK_DRIVE = 'dock_drive_action'

# --- the layer's own names (INTERFACE.md)
#: std_msgs/Empty: vision has failed
VISION_LOST = 'blind_navigation/vision_lost'
#: std_msgs/String: vision back after a loss (vision_monitor): its length and the loss
VISION_BACK = 'blind_navigation/vision_back'
#: std_msgs/Empty, latched: the pi turn begins, the recording ends (back_travel_client)
RECORDING_END = 'blind_navigation/recording_end'
#: service std_srvs/Trigger: the manual trigger, acknowledged (starts the return while recording)
GO_HOME = 'blind_navigation/go_home'
#: service std_srvs/Trigger: stop now, the mission ``aborted`` ("cancelled by request")
CANCEL = 'blind_navigation/cancel'
#: service std_srvs/Trigger: from a terminal state, a new recording in a new mission file
NEW_MISSION = 'blind_navigation/new_mission'
#: std_msgs/String, latched: the mission state (core/mission_state.py)
STATE = 'blind_navigation/state'
#: blind_navigation/MissionStatus, latched: the state with its reason and the return's progress
STATUS = 'blind_navigation/status'
#: nav_msgs/Path for RViz: the path recorded so far, the return driven so far
RECORDED_PATH = 'blind_navigation/recorded_path'
RETURN_PATH = 'blind_navigation/return_path'
#: nav_msgs/Path, latched: the route the return will drive (after pruning), when it starts
RETURN_ROUTE = 'blind_navigation/return_route'
#: action blind_navigation/BackTravel: one landmark per goal
BACK_TRAVEL = 'blind_navigation/back_travel'
#: service blind_navigation/RecordLandmark: the paper's service recorder
RECORD_LANDMARK = 'blind_navigation/record_landmark'

# --- the layer's internal hand-overs
#: blind_navigation/PathSample: sampling publisher -> saver / record client / rotate_pi
SAMPLE = 'blind_navigation/sample'
#: service blind_navigation/RecordedSamples: sampling publisher -> a restarted saver, what it missed
RECORDED_SAMPLES = 'blind_navigation/recorded_samples'
#: blind_navigation/StorageUsage: what the recorded file holds so far
STORAGE = 'blind_navigation/storage'
#: std_msgs/Bool: rotate_pi -> back_travel_client, the pi turn ended (true) or failed
ROTATION_DONE = 'blind_navigation/rotation_done'
#: service blind_navigation/SetReturnRoute: back_travel_client -> back_travel_server
SET_RETURN_ROUTE = 'blind_navigation/set_return_route'
#: std_msgs/String, latched: a role of some process failed (ros/faults.py) -> the mission's owner
ROLE_FAILURE = 'blind_navigation/role_failure'
#: blind_navigation/HeadingCorrection, latched: the gyro correction of the return
HEADING_CORRECTION = 'blind_navigation/heading_correction'
#: geometry_msgs/PoseStamped, latched, paper layout only: a carried reset's frame (docs/safety.md)
ODOMETRY_FRAME = 'blind_navigation/odometry_frame'

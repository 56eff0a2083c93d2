"""Every role's param schema (core/params.py): its user params, and as ``fixed`` constants
the values no user should tune (the core modules' ``*_DEFAULTS`` and the reasons below).
docs/params.md is generated from :data:`SCHEMAS` (scripts/param_table.py)."""
from .allowance import ALLOWANCE_DEFAULTS
from .back_travel import BACK_TRAVEL_DEFAULTS, MODES
from .battery import BATTERY_DEFAULTS, PLAUSIBLE
from .goal import HANDOVER_FOLLOW
from .gyro_bias import STANDSTILL_DEFAULTS
from .gyro_calibration import SPIN_DEFAULTS
from .gyro_fit import GYRO_FIT_DEFAULTS
from .heading_correction import CORRECTION_DEFAULTS
from .mission_state import ON_VISION_BACK
from .motion_events import EVENT_DEFAULTS
from .params import REQUIRED, Param, Schema
from .pause import CONTACT_DEFAULTS, POLICIES, TAKEOVER_DEFAULTS
from .plausibility import KOBUKI_MAX_V, KOBUKI_MAX_W
from .progress import PROGRESS_DEFAULTS
from .pruning import PRUNE_DEFAULTS
from .rotation import ROTATION_DEFAULTS
from .route import ROUTE_DEFAULTS
from .safety import SAFETY_DEFAULTS
from .segment import SAMPLING_DEFAULTS
from .vision import DETECTORS

#: The params every role of a process reads as ``~name`` (not ``~<role>/name``); the
#: takeover's: one watch per process (ros/motion.py) for every role that drives.
SHARED = ('straight_rate', 'standstill_time', 'takeover_wait', 'on_takeover', 'takeover_inputs')
YAW_SOURCES = ('odom', 'pose2d')

STRAIGHT_RATE = Param('straight_rate', SAMPLING_DEFAULTS['straight_rate'], 'Hz', 'the sampling rate '
                      'on straight segments; the server: a landmark with T >= 1 / straight_rate is '
                      'a straight segment', lo=0.01, hi=50.0)
STANDSTILL_TIME = Param('standstill_time', STANDSTILL_DEFAULTS['standstill_time'], 's',
                        'with heading correction: the longest standstill after vision loss '
                        '(0: none), which measures the gyro bias', lo=0.0, hi=3600.0)
ODOM_TIMEOUT = Param('odom_timeout', ALLOWANCE_DEFAULTS['odom_timeout'], 's', 'older odometry is '
                     'stale: the robot holds (zero velocity); a simulator at real-time factor N '
                     'needs N x this', lo=0.01, hi=10.0)
TAKEOVER = (
    Param('takeover_wait', TAKEOVER_DEFAULTS['takeover_wait'], 's', "of operator silence after a "
          'takeover (another publisher on the layer\'s mux input, or a takeover_inputs input '
          'active) before the layer drives again', lo=0.01, hi=600.0),
    Param('on_takeover', TAKEOVER_DEFAULTS['on_takeover'], '', 'after a takeover: resume '
          '(re-track from the new pose) or abort (the mission ends aborted)', choices=POLICIES),
    Param('takeover_inputs', tuple(TAKEOVER_DEFAULTS['takeover_inputs']), '', 'cmd_vel_mux inputs '
          "(their names on cmd_vel_mux/active) above the layer's: one going active is a takeover"),
)
LANDMARK_FILE = Param('landmark_file', '', '', "the symlink to the mission's landmark file "
                      '(empty: blind_navigation/landmarks.yaml under $ROS_HOME); the client only reads it')

SAMPLING_PUBLISHER = Schema('sampling_publisher', (
    STRAIGHT_RATE,
    Param('curved_rate', SAMPLING_DEFAULTS['curved_rate'], 'Hz',
          'the sampling rate on curved segments', lo=0.01, hi=50.0),
    Param('deadband', SAMPLING_DEFAULTS['deadband'], 'rad',
          'a yaw difference this small has no sign (0: the paper\'s literal rule)', lo=0.0, hi=0.5),
    Param('event_sampling', REQUIRED, '', 'true: a sample at each motion event too'),
    Param('min_subscribers', 1, '', 'recording starts once this many nodes take the samples',
          lo=0, hi=100),
    Param('yaw_source', 'odom', '', 'odom, or pose2d (geometry_msgs/Pose2D, as the paper)',
          choices=YAW_SOURCES),
), fixed=dict(SAMPLING_DEFAULTS, **EVENT_DEFAULTS), shared=SHARED)

LANDMARK_SAVING = Schema('landmark_saver', (
    LANDMARK_FILE,
    Param('fsync', True, '', 'fsync every landmark (false: flush only)'),
), fixed={
    'odom_timeout': 1.0,        # s (sim); a sample with older odometry is saved with a warning
    'odom_wait': 0.2,           # s (wall) a sample waits for odometry covering its stamp
    'catch_up_timeout': 3.0,    # s (wall) a restarted saver waits for its samples' connection, then record
})

HEADING_CORRECTION = Schema('heading_correction', (
    Param('gyro_calibration_file', '', '', "calibrate_gyro.launch's YAML "
          '(empty: blind_navigation/gyro_calibration.yaml under $ROS_HOME)'),
    STANDSTILL_TIME,
), fixed=dict(GYRO_FIT_DEFAULTS, **CORRECTION_DEFAULTS, **STANDSTILL_DEFAULTS,
              standstill_timeout=None,  # unset: core/gyro_bias.standstill_timeout
              vo_timeout=10.0),         # s without visual odometry before it warns
    shared=SHARED)

ROTATE_PI = Schema('rotate_pi', (
    Param('wait_for_heading_correction', REQUIRED, '', 'true: turn once the heading correction is in'),
    STANDSTILL_TIME,
    ODOM_TIMEOUT,
    Param('recording_end_timeout', 1.0, 's', "(sim) the turn waits this long for the recorder's "
          'final sample', lo=0.0, hi=60.0),
) + TAKEOVER, fixed=dict(ROTATION_DEFAULTS,
              control_rate=50.0,          # Hz of the turn's control loop (the odometry's rate)
              odom_grace=ALLOWANCE_DEFAULTS['odom_grace'],
              correction_margin=25.0),    # s added to the standstill's timeout: the longest
              shared=SHARED)              # wait for the heading correction

BACK_TRAVEL_SERVER = Schema('back_travel_server', (
    Param('control', REQUIRED, '', 'time, distance or closed_loop (core/goal.py)', choices=MODES),
    STRAIGHT_RATE,
    Param('stop_lead', BACK_TRAVEL_DEFAULTS['stop_lead'], 's', 'closed_loop: the robot coasts '
          'this long after its last command', lo=0.0, hi=2.0),
    Param('max_v', BACK_TRAVEL_DEFAULTS['max_v'], 'm/s', 'hard clamp on |v|', lo=0.01, hi=KOBUKI_MAX_V),
    Param('handover_follow', HANDOVER_FOLLOW, 's', 'closed_loop: between two goals the follower '
          'goes on driving the route this long while the next goal comes (core/goal.HandoverBridge); '
          '0: the last command holds 0.1 s, then zero', lo=0.0, hi=2.0),
    ODOM_TIMEOUT,
    Param('contact_wait', CONTACT_DEFAULTS['contact_wait'], 's', 'after a bumper release before '
          'the return goes on (docs/safety.md, Contacts)', lo=0.0, hi=600.0),
    Param('max_contacts', CONTACT_DEFAULTS['max_contacts'], '', 'bumper contacts one return '
          'survives; the next one ends it aborted', lo=0, hi=1000),
    Param('contact_timeout', CONTACT_DEFAULTS['contact_timeout'], 's', 'a bumper contact may last '
          'this long from its first press (bounces included) before the return ends aborted',
          lo=0.01, hi=3600.0),
) + TAKEOVER, fixed=dict({k: v for k, v in BACK_TRAVEL_DEFAULTS.items() if k != 'straight_period'},
              **ALLOWANCE_DEFAULTS,
              control_rate=50.0,          # Hz of the control loop (the odometry's rate)
              feedback_rate=5.0,          # Hz of the action's feedback
              handover_timeout=0.1,       # s the last command holds after a goal, between goals
              status_frequency=1.0),      # Hz of the action server's periodic status
    shared=SHARED)

BACK_TRAVEL_CLIENT = Schema('back_travel_client', (
    LANDMARK_FILE,
    Param('heading_correction', REQUIRED, '', 'true: the landmarks in the heading-corrected frame'),
    Param('prune_loops', REQUIRED, '', 'true: cut loops from the route (core/pruning; closed_loop)'),
    STANDSTILL_TIME,
    Param('odom_timeout', 0.5, 's', 'older odometry counts as missing (the client; simulator: '
          'N x this at real-time factor N)', lo=0.01, hi=10.0),
    Param('server_timeout', 10.0, 's', 'the wait for the back-travel server', lo=0.1, hi=600.0),
    Param('return_timeout_factor', ALLOWANCE_DEFAULTS['return_timeout_factor'], '',
          "the whole return's allowance: factor x its nominal time + margin", lo=0.01, hi=100.0),
    Param('return_timeout_margin', ALLOWANCE_DEFAULTS['return_timeout_margin'], 's',
          "added to the whole return's allowance", lo=0.0, hi=3600.0),
    Param('vision_back_grace', STANDSTILL_DEFAULTS['standstill_min'], 's', 'without '
          "heading_correction's standstill: the pi turn waits this long after vision loss for "
          'vision to come back (a brief loss: the mission goes on); 0: at once (paper.launch)',
          lo=0.0, hi=600.0),
    Param('on_vision_back', 'home', '', 'vision back during the pi turn or the return: home (go '
          'on home, the paper\'s) or stop (stop, state recovered)', choices=ON_VISION_BACK),
) + TAKEOVER, fixed=dict(ROUTE_DEFAULTS, **PRUNE_DEFAULTS, **{
    'goal_timeout_factor': 5.0,     # a goal may go factor x its expected time + margin s without
    'goal_timeout_margin': 10.0,    # a result or feedback: a backstop for a silent server
    'slowest_v': SAFETY_DEFAULTS['slowest_v'],
    'max_v': KOBUKI_MAX_V,          # m/s; a landmark faster than this is a bad file
    'max_w': KOBUKI_MAX_W,          # rad/s; a landmark turning faster is a bad file
    'resume_timeout': PROGRESS_DEFAULTS['resume_timeout'],
    'resume_max_offset': PROGRESS_DEFAULTS['resume_max_offset'],
    'path_spacing': 0.02,           # m between the poses of return_path (RViz only)
    'correction_timeout': 5.0,      # s the return waits for the heading correction (none: aborted)
    'rotation_margin': 60.0,        # s + standstill timeout + vision_back_grace: the rotation_timeout
    'turn_tolerance': 0.3,          # rad a finished pi turn may differ from pi
}), shared=SHARED)

VISION_MONITOR = Schema('vision_monitor', (
    Param('detectors', ('stall', 'vo_lost', 'vo_stall', 'odom_info', 'manual'), '', 'the detectors '
          'that run: stall (camera_info; the images with dark), dark (dark images: reads every '
          "frame), vo_lost (RTAB-Map's null pose), vo_stall, odom_info (RTAB-Map's lost flag), "
          "manual (a vision_lost another node publishes, the paper's way); docs/detection.md",
          choices=DETECTORS),
    Param('vision_back_time', 1.0, 's', 'every detector healthy this long after a loss: vision '
          'back (a brief loss; on_vision_back)', lo=0.01, hi=600.0),
), fixed={
    'debounce': 0.5,             # s a detector's condition must hold before it fires
    'image_timeout': 1.0,        # s without a camera message: a stall (camera at >= 10 Hz)
    'vo_timeout': 1.0,           # s without visual odometry: a stall
    'dark_threshold': 10.0,      # mean intensity (0..255) below which an image is dark
    'dark_frames': 3,            # consecutive dark images before it counts
    'no_input_warning': 5.0,     # s with no camera or visual odometry before it warns
    'host_stall_gap': 0.5,       # s without wheel odometry too: the host stalled (core/vision.HostFlow)
})

CALIBRATE_GYRO = Schema('calibrate_gyro', (
    Param('calibration_file', '', '', 'the calibration YAML written '
          '(empty: blind_navigation/gyro_calibration.yaml under $ROS_HOME)'),
    Param('turns', SPIN_DEFAULTS['turns'], '', 'full turns each way: scale std ~0.005 / '
          'sqrt(2 pi turns x 2)', lo=0.5, hi=50.0),
    Param('max_w', SPIN_DEFAULTS['max_w'], 'rad/s', 'cruise turn rate of the spins',
          lo=0.1, hi=KOBUKI_MAX_W),
    Param('odom_timeout', 0.4, 's', 'older odometry fails the calibration (scale with a '
          "simulator's real-time factor)", lo=0.01, hi=60.0),
    Param('start_timeout', 30.0, 's', '(wall) the wait for odometry and visual odometry',
          lo=0.1, hi=3600.0),
), fixed=dict(SPIN_DEFAULTS, **GYRO_FIT_DEFAULTS, max_scale=CORRECTION_DEFAULTS['max_scale'],
              control_rate=50.0))         # Hz of the spin's control loop (the odometry's rate)

MISSION_OWNER = Schema('mission_owner', (
    Param('battery_low', 0.0, 'V', 'the one process only: the Kobuki battery (mobile_base/sensors/core) '
          'below this while recording starts the return as go_home does (its median held '
          'battery_hold s, never one reading: core/battery.py); 0: off', lo=0.0, hi=PLAUSIBLE[1]),
    Param('dock_at_home', False, '', 'the one process only: true: once home, dock on the Kobuki\'s '
          'charging dock with its auto-docking action dock_drive_action (states docking, docked; '
          'core/docking.py)'),
), fixed=BATTERY_DEFAULTS)

#: Every role's schema, in the order the docs list them.
SCHEMAS = (SAMPLING_PUBLISHER, LANDMARK_SAVING, HEADING_CORRECTION, ROTATE_PI,
           BACK_TRAVEL_SERVER, BACK_TRAVEL_CLIENT, VISION_MONITOR, CALIBRATE_GYRO, MISSION_OWNER)

"""Vision-loss detectors (core/vision.py): each detector, debounce, flicker, re-arming."""
import struct

import numpy
import pytest

from blind_navigation.core.odometry_wire import WireOdometry
from blind_navigation.core.vision import (DETECTORS, Debounce, VisionBack, VisionLossMonitor,
                                          image_mean_intensity, odom_info_lost, wire_lost_reason)

DT = 0.05  # 20 Hz messages
GOOD_VO = ((1.0, 2.0, 0.0), (0.0, 0.0, 0.38, 0.92), [0.01] * 6, [0.01] * 6)
LOST_VO = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 0.0), [9999.0] * 6, [9999.0] * 6)


def vo_lost_reason(position, orientation, pose_covariance, twist_covariance):
    """core/vision.wire_lost_reason of a VO message with these fields (the wire has no z)."""
    return wire_lost_reason(WireOdometry(0.0, 'odom', position[0], position[1], *orientation,
                                         pose_covariance, 0.0, 0.0, twist_covariance))


def times(start, end, dt=DT):
    """Message stamps in [start, end)."""
    count = int(round((end - start) / dt))
    return [start + i * dt for i in range(count)]


def feed_images(monitor, start, end, mean):
    losses = []
    for t in times(start, end):
        losses += monitor.image(t, mean)
        losses += monitor.check(t)
    return losses


def feed_vo(monitor, start, end, vo):
    losses = []
    for t in times(start, end):
        losses += monitor.vo_odometry(t, vo_lost_reason(*vo))
        losses += monitor.check(t)
    return losses


def silence(monitor, start, end):
    losses = []
    for t in times(start, end):
        losses += monitor.check(t)
    return losses


# --- Debounce ----------------------------------------------------------------------------------

def test_debounce_fires_once_after_hold_and_rearms():
    debounce = Debounce(0.5)
    fired = [t for t in times(0.0, 2.0) if debounce.update(t, True)]
    assert fired == [pytest.approx(0.5)]
    assert not debounce.update(2.0, False)
    fired = [t for t in times(3.0, 4.0) if debounce.update(t, True)]
    assert fired == [pytest.approx(3.5)]


def test_debounce_min_count_holds_even_when_time_passed():
    debounce = Debounce(0.1, min_count=3)
    assert [debounce.update(t, True) for t in (0.0, 1.0, 2.0)] == [False, False, True]


def test_debounce_rejects_bad_settings():
    with pytest.raises(ValueError):
        Debounce(-1.0)
    with pytest.raises(ValueError):
        Debounce(0.5, min_count=0)


# --- camera stall ------------------------------------------------------------------------------

def test_stall_not_armed_before_first_image():
    monitor = VisionLossMonitor({'stall'})
    assert silence(monitor, 0.0, 10.0) == []
    assert monitor.stall.last is None


def test_stall_fires_after_timeout_plus_debounce_once():
    monitor = VisionLossMonitor({'stall'}, image_timeout=1.0, debounce=0.5)
    assert feed_images(monitor, 0.0, 2.0, 100.0) == []
    last_image = 2.0 - DT
    losses = silence(monitor, 2.0, 6.0)
    assert [loss.detector for loss in losses] == ['stall']
    assert losses[0].t == pytest.approx(last_image + 1.5, abs=DT + 1e-9)
    assert losses[0].since == pytest.approx(last_image)
    assert 'no image' in losses[0].reason


def test_stall_gap_shorter_than_timeout_plus_debounce_does_not_fire_and_rearms():
    monitor = VisionLossMonitor({'stall'}, image_timeout=1.0, debounce=0.5)
    feed_images(monitor, 0.0, 1.0, 100.0)
    assert silence(monitor, 1.0, 2.3) == []           # stalled 0.3 s past the timeout
    assert feed_images(monitor, 2.3, 3.0, 100.0) == []
    assert len(silence(monitor, 3.0, 5.0)) == 1       # a real stall still fires
    assert feed_images(monitor, 5.0, 5.5, 100.0) == []  # recovered: re-armed
    assert len(silence(monitor, 5.5, 8.0)) == 1


# --- dark images -------------------------------------------------------------------------------

def test_dark_fires_after_debounce_once():
    monitor = VisionLossMonitor({'dark'}, debounce=0.5, dark_threshold=10.0, dark_frames=3)
    assert feed_images(monitor, 0.0, 1.0, 120.0) == []
    losses = feed_images(monitor, 1.0, 4.0, 2.0)
    assert len(losses) == 1
    assert losses[0].detector == 'dark'
    assert losses[0].t == pytest.approx(1.5)
    assert losses[0].since == pytest.approx(1.0)
    assert 'mean intensity 2.0 < 10.0' in losses[0].reason


def test_dark_flicker_of_0_3_s_does_not_fire():
    monitor = VisionLossMonitor({'dark'}, debounce=0.5)
    feed_images(monitor, 0.0, 1.0, 120.0)
    assert feed_images(monitor, 1.0, 1.3, 0.0) == []
    assert feed_images(monitor, 1.3, 3.0, 120.0) == []


def test_dark_needs_the_frame_count_at_low_frame_rate():
    monitor = VisionLossMonitor({'dark'}, debounce=0.5, dark_frames=3)
    assert monitor.image(0.0, 0.0) == []
    assert monitor.image(1.0, 0.0) == []               # 1 s of dark but only 2 frames
    assert [loss.detector for loss in monitor.image(2.0, 0.0)] == ['dark']


def test_dark_rearms_after_bright_frames():
    monitor = VisionLossMonitor({'dark'}, debounce=0.5)
    assert len(feed_images(monitor, 0.0, 1.0, 0.0)) == 1
    assert feed_images(monitor, 1.0, 1.2, 100.0) == []
    assert len(feed_images(monitor, 1.2, 2.0, 0.0)) == 1


def test_disabled_detector_never_fires():
    monitor = VisionLossMonitor({'stall'}, debounce=0.5)
    assert feed_images(monitor, 0.0, 3.0, 0.0) == []


# --- RTAB-Map VO lost --------------------------------------------------------------------------

def test_vo_lost_reasons():
    assert vo_lost_reason(*GOOD_VO) is None
    assert vo_lost_reason(*LOST_VO) == 'VO null quaternion'
    big_cov = ((1.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), [0.1, 0.1, 9999.0, 0.1, 0.1, 0.1], [0.1] * 6)
    assert 'covariance 9999' in vo_lost_reason(*big_cov)
    nan_pose = ((float('nan'), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), [0.1] * 6, [0.1] * 6)
    assert 'not finite' in vo_lost_reason(*nan_pose)
    nan_cov = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0), [float('nan')] * 6, [0.1] * 6)
    assert vo_lost_reason(*nan_cov) is not None


def test_vo_lost_fires_once_and_flicker_does_not():
    monitor = VisionLossMonitor({'vo_lost'}, debounce=0.5)
    assert feed_vo(monitor, 0.0, 1.0, GOOD_VO) == []
    assert feed_vo(monitor, 1.0, 1.3, LOST_VO) == []   # 0.3 s flicker
    assert feed_vo(monitor, 1.3, 2.0, GOOD_VO) == []
    losses = feed_vo(monitor, 2.0, 5.0, LOST_VO)
    assert [(loss.detector, round(loss.t, 6)) for loss in losses] == [('vo_lost', 2.5)]
    assert feed_vo(monitor, 5.0, 5.5, GOOD_VO) == []
    assert len(feed_vo(monitor, 5.5, 7.0, LOST_VO)) == 1  # re-armed


def test_vo_stall_fires_when_vo_stops():
    monitor = VisionLossMonitor({'vo_stall'}, vo_timeout=1.0, debounce=0.5)
    feed_vo(monitor, 0.0, 1.0, GOOD_VO)
    losses = silence(monitor, 1.0, 4.0)
    assert [loss.detector for loss in losses] == ['vo_stall']
    assert losses[0].t == pytest.approx(1.0 - DT + 1.5, abs=DT + 1e-9)


def test_vo_stall_fires_while_wheel_odometry_flows():
    monitor = VisionLossMonitor({'vo_stall'}, vo_timeout=1.0, debounce=0.5)
    losses = []
    for t in times(0.0, 4.0):
        monitor.host_flow(t)                 # the wheel odometry goes on
        if t < 1.0:
            losses += monitor.vo_odometry(t, None)
        losses += monitor.check(t)
    assert [loss.detector for loss in losses] == ['vo_stall']
    assert losses[0].t == pytest.approx(1.0 - DT + 1.5, abs=DT + 1e-9)   # as without it


def test_a_host_stall_is_no_vision_loss():
    """The whole host stalls 1.8 s (every stream silent, the soak's second hour); the
    first check after it runs before any message is read; then the backlog comes,
    wheel odometry first: nothing fires."""
    monitor = VisionLossMonitor({'vo_stall', 'stall'}, vo_timeout=1.0, debounce=0.5)
    for t in times(0.0, 2.0):
        monitor.host_flow(t)
        monitor.vo_odometry(t, None)
        monitor.image(t, None)
    assert monitor.check(3.8) == []          # the stall's end: nothing read yet
    monitor.host_flow(3.8)
    assert monitor.check(3.81) == []         # wheel odometry resumed, VO not read yet
    monitor.host_flow(3.85)
    assert monitor.check(3.9) == []
    monitor.vo_odometry(3.9, None)
    monitor.image(3.9, None)
    assert silence(monitor, 3.95, 5.0) == []
    assert monitor.vo_stall.due(4.0, monitor.host) == pytest.approx(3.9 + 1.5)


def test_stall_checks_are_due_when_a_stall_could_fire():
    monitor = VisionLossMonitor({'vo_stall'}, vo_timeout=1.0, debounce=0.5)
    stall, host = monitor.vo_stall, monitor.host
    assert stall.due(2.0) == stall.due(2.0, host) == pytest.approx(3.5)   # unarmed: from now
    monitor.vo_odometry(1.0, None)
    monitor.host_flow(1.0)
    assert stall.due(1.2, host) == pytest.approx(2.5)
    assert stall.due(2.0, host) == pytest.approx(2.5)          # overdue: check at once
    assert stall.due(3.0, host) == pytest.approx(3.5)          # host silent: again in its gap
    monitor.host_flow(3.0)                                     # resumed
    assert stall.due(3.0, host) == pytest.approx(4.5)


def test_vo_stall_after_a_host_stall_counts_from_the_resumption():
    monitor = VisionLossMonitor({'vo_stall'}, vo_timeout=1.0, debounce=0.5)
    for t in times(0.0, 2.0):
        monitor.host_flow(t)
        monitor.vo_odometry(t, None)
    losses = []
    for t in times(3.8, 7.0):                # the host resumed; visual odometry never does
        monitor.host_flow(t)
        losses += monitor.check(t)
    assert [loss.detector for loss in losses] == ['vo_stall']
    assert losses[0].t == pytest.approx(3.8 + 1.5, abs=DT + 1e-9)
    assert losses[0].since == pytest.approx(2.0 - DT)          # the last VO message


def test_without_wheel_odometry_the_stall_detectors_work_as_before():
    monitor = VisionLossMonitor({'vo_stall'}, vo_timeout=1.0, debounce=0.5)
    feed_vo(monitor, 0.0, 1.0, GOOD_VO)
    assert monitor.host.flowing(10.0)
    assert [loss.detector for loss in silence(monitor, 1.0, 4.0)] == ['vo_stall']
    with pytest.raises(ValueError):
        VisionLossMonitor({'vo_stall'}, host_gap=0.0)


# --- odom_info lost flag -----------------------------------------------------------------------

def odom_info_bytes(lost, frame_id=b'odom'):
    """What rtabmap_ros/OdomInfo serialises to up to ``matches`` (little endian)."""
    header = struct.pack('<III', 7, 100, 5) + struct.pack('<I', len(frame_id)) + frame_id
    return header + struct.pack('<B', 1 if lost else 0) + struct.pack('<ii', 120, 80)


def test_odom_info_lost_flag_parsed_after_the_header():
    assert odom_info_lost(odom_info_bytes(True)) is True
    assert odom_info_lost(odom_info_bytes(False)) is False
    assert odom_info_lost(odom_info_bytes(True, frame_id=b'a_much_longer_frame_id')) is True
    with pytest.raises(ValueError):
        odom_info_lost(odom_info_bytes(True)[:12])
    with pytest.raises(ValueError):
        odom_info_lost(struct.pack('<IIII', 1, 2, 3, 4))


def test_odom_info_detector_debounced():
    monitor = VisionLossMonitor({'odom_info'}, debounce=0.5)
    flags = [monitor.odom_info_flag(t, 1.0 <= t < 1.3) for t in times(0.0, 2.0)]
    assert not any(flags)
    losses = sum((monitor.odom_info_flag(t, True) for t in times(2.0, 3.0)), [])
    assert [(loss.detector, round(loss.t, 6)) for loss in losses] == [('odom_info', 2.5)]


# --- manual, bundle ----------------------------------------------------------------------------

def test_manual_fires_at_once_and_can_be_disabled():
    assert [loss.detector for loss in VisionLossMonitor(DETECTORS).manual(3.0, '/operator')] \
        == ['manual']
    assert VisionLossMonitor({'stall'}).manual(3.0, '/operator') == []


def test_unknown_detector_name_is_refused():
    with pytest.raises(ValueError, match='blur'):
        VisionLossMonitor({'stall', 'blur'})


def test_clock_jumping_back_resets_the_detectors():
    monitor = VisionLossMonitor({'stall', 'dark'}, debounce=0.5)
    feed_images(monitor, 10.0, 10.4, 0.0)              # 0.4 s dark so far
    assert feed_images(monitor, 0.0, 0.3, 0.0) == []   # sim restarted: debounce starts over
    assert silence(monitor, 0.3, 0.5) == []


# --- image mean --------------------------------------------------------------------------------

def test_image_mean_for_common_encodings():
    pixels = numpy.full((48, 64, 3), (30, 60, 90), dtype=numpy.uint8)
    assert image_mean_intensity('rgb8', 48, 64, 64 * 3, pixels.tobytes()) == pytest.approx(60.0)
    assert image_mean_intensity('bgr8', 48, 64, 64 * 3, pixels.tobytes()) == pytest.approx(60.0)
    mono = numpy.full((48, 64), 200, dtype=numpy.uint8)
    assert image_mean_intensity('mono8', 48, 64, 64, mono.tobytes()) == pytest.approx(200.0)
    rgba = numpy.full((48, 64, 4), (0, 0, 0, 255), dtype=numpy.uint8)
    assert image_mean_intensity('rgba8', 48, 64, 256, rgba.tobytes()) == pytest.approx(0.0)
    mono16 = numpy.full((48, 64), 257 * 100, dtype='>u2')
    assert image_mean_intensity('mono16', 48, 64, 128, mono16.tobytes(), is_bigendian=True) \
        == pytest.approx(100.0)


def test_image_mean_skips_row_padding():
    rows = numpy.zeros((10, 40), dtype=numpy.uint8)
    rows[:, :30] = 50      # 10 rgb pixels per row, then 10 bytes of padding
    rows[:, 30:] = 255
    assert image_mean_intensity('rgb8', 10, 10, 40, rows.tobytes()) == pytest.approx(50.0)


def test_image_mean_subsamples_large_images_accurately():
    rng = numpy.random.RandomState(0)
    pixels = rng.randint(0, 256, size=(480, 640, 3)).astype(numpy.uint8)
    mean = image_mean_intensity('rgb8', 480, 640, 640 * 3, pixels.tobytes())
    assert mean == pytest.approx(float(pixels.mean()), abs=1.0)


def test_image_mean_refuses_bad_input():
    with pytest.raises(ValueError, match='32FC1'):
        image_mean_intensity('32FC1', 2, 2, 16, bytes(64))
    with pytest.raises(ValueError, match='do not match'):
        image_mean_intensity('rgb8', 48, 64, 64 * 3, bytes(100))


# --- vision back -------------------------------------------------------------------------------

def back_times(back, monitor, start, end, vo, feed_image=None):
    """Stamps in [start, end) at which ``back`` fired, VO ``vo`` (None: silent) and images."""
    fired = []
    for t in times(start, end):
        if vo is not None:
            monitor.vo_odometry(t, vo_lost_reason(*vo))
        if feed_image is not None:
            monitor.image(t, feed_image)
        monitor.check(t)
        if back.update(t):
            fired.append(round(t, 6))
    return fired


def test_vision_back_after_a_vo_loss_needs_the_whole_hold_once():
    monitor = VisionLossMonitor({'vo_lost', 'vo_stall'}, debounce=0.5)
    feed_vo(monitor, 0.0, 1.0, GOOD_VO)
    assert len(feed_vo(monitor, 1.0, 4.0, LOST_VO)) == 1      # a 3 s loss
    back = VisionBack(monitor, 1.0)
    assert back_times(back, monitor, 1.5, 4.0, LOST_VO) == []
    assert back_times(back, monitor, 4.0, 4.5, GOOD_VO) == []
    assert back_times(back, monitor, 4.5, 4.8, LOST_VO) == []  # a relapse restarts the hold
    assert back_times(back, monitor, 4.8, 7.0, GOOD_VO) == [5.8]


def test_vision_is_not_back_while_a_watched_stream_is_silent():
    monitor = VisionLossMonitor({'vo_stall', 'dark'}, vo_timeout=1.0, debounce=0.5)
    feed_vo(monitor, 0.0, 1.0, GOOD_VO)
    back = VisionBack(monitor, 0.5)
    assert back_times(back, monitor, 1.0, 3.0, GOOD_VO) == []          # no image yet
    assert monitor.unhealthy(3.0) == 'no image'
    assert back_times(back, monitor, 3.0, 4.0, GOOD_VO, feed_image=0.0) == []   # dark
    assert back_times(back, monitor, 4.0, 5.0, GOOD_VO, feed_image=100.0) == [4.5]
    assert back_times(back, monitor, 5.0, 7.0, None) == []              # the VO stalls


def test_vision_back_needs_a_watched_stream_and_a_positive_hold():
    assert VisionLossMonitor({'manual'}).unhealthy(1.0) == 'no camera or visual-odometry stream watched'
    with pytest.raises(ValueError, match='vision_back_time'):
        VisionBack(VisionLossMonitor({'vo_lost'}), 0.0)

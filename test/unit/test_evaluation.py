"""Unit tests of the bench (blind_navigation/evaluation): the numbers it reports
are computed as documented, and its forward recording is the harness's own."""
import math
import os

import pytest

from blind_navigation.core.geometry import OdomState, Pose2D, quaternion_from_yaw
from blind_navigation.core.landmark import Landmark
from blind_navigation.sim.harness import run_mission
from blind_navigation.evaluation import paper, tables
from blind_navigation.evaluation.forward import ForwardRecord, harness_settings, record_forward
from blind_navigation.evaluation.montecarlo import landmark_stats, return_geometry, run_job
from blind_navigation.evaluation.reconstruction import compare_sampling, deviation, rebuild_path
from blind_navigation.evaluation.report import markdown_table, med_range, med_worst, farthest_from_zero
from blind_navigation.evaluation.tum import forward_trajectories, read_tum, write_tum


def test_record_forward_is_the_harness_recording():
    forward = record_forward('table6_test1', 'paper', seed=3)
    result = run_mission('table6_test1', 'paper', 'time', seed=3)
    assert len(forward.landmarks) == result.samples
    assert forward.bytes == result.bytes
    assert sum(lm.d for lm in forward.landmarks) == pytest.approx(result.distance, abs=1e-6)
    end = forward.truth[-1][1]
    assert math.hypot(end.x - result.forward_path[-1][0], end.y - result.forward_path[-1][1]) < 0.006
    assert len(forward.odometry) == len(forward.truth)
    assert forward.truth[1][0] - forward.truth[0][0] == pytest.approx(0.02)   # 50 Hz


def test_harness_settings_rejects_unknown_names():
    with pytest.raises(ValueError, match='bogus'):
        harness_settings(bogus=1)


def _lm(v, w=0.0, d=0.1, T=2.0, psi=0.0):
    return Landmark(v, w, d, T, psi)


def test_landmark_stats_counts_and_moving_minimum():
    # ticks at 2, 4, 6, 7, 9 s; recording 9 s, settle 2 s -> operator until 7 s
    landmarks = [_lm(0.01), _lm(0.06, 0.2), _lm(0.04, -0.3), _lm(0.05, T=1.0), _lm(0.0)]
    stats = landmark_stats(landmarks, sv=0.05, asv=0.25, settle_time=2.0)
    assert stats['rlv_max'] == 0.06
    assert stats['rlv_min'] == 0.04          # not the start-up 0.01 nor the stopped 0.0
    assert stats['over'] == 1
    assert (stats['rav_max'], stats['rav_min'], stats['rav_over']) == (0.2, -0.3, 1)
    assert stats['curved'] == 1


def test_return_geometry_straight_back_and_short():
    forward = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)]
    exact = return_geometry(forward, [(2.0, 0.0), (0.0, 0.0)])
    assert exact['d'] == pytest.approx(2.0) and exact['cd'] == pytest.approx(2.0)
    assert exact['pe'] == pytest.approx(0.0) and exact['back_hd'] == pytest.approx(0.0)
    short = return_geometry(forward, [(2.0, 0.0), (0.2, 0.1)])
    assert short['pe'] == pytest.approx(100.0 * (2.0 - math.hypot(1.8, 0.1)) / 2.0)
    assert short['back_hd'] == pytest.approx(-math.atan2(0.1, 1.8))   # drifted left = negative w.r.t. pi


def test_deviation_point_to_polyline():
    line = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)]
    d = deviation([(0.5, 0.2), (1.3, 0.5), (-1.0, 0.0)], line)
    assert list(d) == pytest.approx([0.2, 0.3, 1.0])


def test_rebuild_path_of_a_straight_line_is_exact():
    landmarks = [_lm(0.1, d=0.2, psi=0.0) for _ in range(5)]
    rebuilt = rebuild_path(landmarks, (1.0, 0.0))
    assert rebuilt[0] == pytest.approx((0.0, 0.0))
    assert rebuilt[-1] == pytest.approx((1.0, 0.0))
    assert len(rebuilt) == 6


def test_compare_sampling_same_count_and_small_error_on_ideal_robot():
    out = compare_sampling('table6_test1', 'ideal', 0)
    assert abs(out['adaptive']['samples'] - out['uniform']['samples']) <= 1
    for kind in ('adaptive', 'uniform'):
        assert out[kind]['truth_max'] < 0.05        # the ideal robot: the chord error only
        assert out[kind]['truth_mean'] <= out[kind]['truth_max']


def test_run_job_rows_per_mode():
    rows = run_job(('table3_test5', 'paper', 1, ('time', 'distance', 'closed_loop'), True))
    assert [r['mode'] for r in rows] == ['time', 'distance', 'closed_loop']
    assert [r['deadband'] for r in rows] == [0.0, 0.0, 0.01]  # paper.launch vs blind_navigation.launch
    assert rows[0]['samples'] == rows[1]['samples']          # same configuration: same forward run
    assert rows[0]['rlv_max'] == rows[1]['rlv_max']
    assert all(r['status'] == 'home' and r['error'] >= 0 and 'return_path' in r for r in rows)


def test_tum_round_trip(tmp_path):
    poses = [(0.0, 0.0, 0.0, 0.0), (0.02, 0.1, -0.2, 1.0)]
    path = write_tum(str(tmp_path / 'a' / 'x.tum'), poses)
    back = read_tum(path)
    assert back[1][:4] == pytest.approx((0.02, 0.1, -0.2, 0.0))
    assert back[1][4:] == pytest.approx(quaternion_from_yaw(1.0), abs=1e-6)
    bad = tmp_path / 'bad.tum'
    bad.write_text('1 2 3\n')
    with pytest.raises(ValueError, match='bad.tum:1'):
        read_tum(str(bad))


def test_forward_trajectories_align_in_time():
    odom = [OdomState(0.1 * i, 0.0, 0.0, 0.1, 0.0, 0.0) for i in range(3)]
    truth = [(0.02 * (i + 1), Pose2D(0.1 * i, 0.0, 0.0)) for i in range(3)]
    record = ForwardRecord('m', [_lm(0.1, d=0.2, T=2.0, psi=0.1)], 100, (0.2, 0.0), odom, truth, 0.06)
    out = forward_trajectories(record, [(0.0, 0.0), (0.2, 0.0)])
    assert [p[0] for p in out['ground_truth']] == [p[0] for p in out['odometry']]
    assert out['landmarks'] == [(0.0, 0.0, 0.0, 0.0), (2.0, 0.2, 0.0, 0.1)]


def test_report_formats():
    assert med_worst([0.1, 0.3, 0.2]) == '0.200 (0.300)'
    assert med_worst([1.0, -3.0, 2.0], 1, farthest_from_zero) == '1.0 (-3.0)'
    assert med_range([3, 1, 2], 0) == '2 [1..3]'
    assert med_worst([]) == '—'
    assert markdown_table(['a', 'b'], [[1, 2]]) == '| a | b |\n|---|---|\n| 1 | 2 |\n'


def test_table6_puts_the_paper_beside_ours():
    rows = [{'mission': 'table6_test2', 'mode': mode, 'seed': s, 'length': 3.8, 'samples': 25,
             'bytes': 2048, 'error': e} for s, e in enumerate((0.1, 0.3)) for mode in ('time', 'closed_loop')]
    text = tables.table6(rows)
    line = [l for l in text.splitlines() if l.startswith('| table6_test2')][0]
    assert '43 / 25' in line and '5 / 2.0' in line and '| 0.28 |' in line
    assert '0.200 (0.300)' in line
    assert paper.TABLE6['table6_test6']['error'] == 1.3


def test_odom_bag_has_one_message_per_step(tmp_path):
    rosbag = pytest.importorskip('rosbag')
    from blind_navigation.evaluation.storage import write_odom_bag
    odom = [OdomState(0.01 * i, 0.0, 0.0, 0.1, 0.0, 0.0) for i in range(50)]
    truth = [(0.02 * (i + 1), Pose2D(0.01 * i, 0.0, 0.0)) for i in range(50)]
    record = ForwardRecord('m', [], 0, (0.0, 0.0), odom, truth, 1.0)
    size = write_odom_bag(str(tmp_path / 'o.bag'), record)
    assert size == os.path.getsize(str(tmp_path / 'o.bag'))
    with rosbag.Bag(str(tmp_path / 'o.bag')) as bag:
        messages = list(bag.read_messages(topics=['/odom']))
    assert len(messages) == 50
    msg = messages[10].message
    assert msg.pose.pose.position.x == pytest.approx(0.1)
    assert msg.header.stamp.to_sec() == pytest.approx(0.22)
    assert msg.pose.covariance[35] == 0.05


def test_agreement_table_sets_ros_beside_the_same_harness_seed():
    from blind_navigation.evaluation.bench import agreement_table
    ros = [{'mission': 'table6_test1', 'mode': 'time', 'seed': s, 'state': 'home', 'samples': 24,
            'stationary_samples': 6, 'length': 2.6, 'error': e, 'rtf': 5.0, 'vision_failure': 'dark'}
           for s, e in ((0, 0.05), (1, 0.31))]
    harness = [{'mission': 'table6_test1', 'mode': 'time', 'seed': s, 'samples': 18, 'length': 2.64,
                'error': 0.1 + s} for s in range(4)]
    text = agreement_table(ros, harness)
    assert '| table6_test1 | time | 1 | home | 18 (+6 before the start) | 18 | 2.60 | 2.64 | 0.310 | 1.100 | 5.0 |' in text
    assert '| table6_test1 | time | 2 | 0.180 [0.050..0.310] | 0.600 [0.100..1.100] | 1.600 [0.100..3.100] (4 seeds) |' in text


def test_log_findings_reads_the_abort_reason_and_overload(tmp_path):
    from blind_navigation.evaluation.ros_runs import log_findings
    log = tmp_path / 'launch.log'
    log.write_text('[INFO] /back_travel_client: state rotating -> returning\n'
                   '[WARN] fake_kobuki: behind real time x 5.0\n'
                   '[ERROR] /back_travel_client: state returning -> aborted: goal 11/72 ended ABORTED: stale\n'
                   '[WARN] fake_kobuki: behind real time x 5.0\n')
    assert log_findings(str(log)) == ('goal 11/72 ended ABORTED: stale', 2, 'aborted')


def test_loops_rows_pair_the_pruned_return_with_the_unpruned_one():
    from blind_navigation.evaluation import loops
    rows = loops.run_job(('dead_end', 'dead_end', 2, None))
    unpruned, pruned = rows
    assert (unpruned['mode'], pruned['mode']) == ('unpruned', 'pruned')
    assert unpruned['length'] == pruned['length'] and unpruned['cuts'] == 0 < pruned['cuts']
    assert pruned['length_ratio'] == pytest.approx(pruned['return_length'] / unpruned['return_length'])
    assert pruned['length_ratio'] < 0.8 and unpruned['length_ratio'] == 1.0
    assert len(pruned['true_gaps']) == pruned['cuts'] and pruned['true_gap_max'] < 0.3
    text = loops.table(rows)
    assert '| dead_end | 1 | 0 / 0 |' in text and '**all loop paths**' in text
    verdict, met = loops.verdict(rows)
    assert 'none aborted: met' in verdict and isinstance(met, bool)


def test_survival_table_counts_survivors_and_errors_of_those_home():
    from blind_navigation.evaluation.survival import table
    runs = [dict(case='brief', seed=0, survived=True, state='home', error=0.02, error_pct=1.0, contacts=0),
            dict(case='brief', seed=1, survived=False, state='home', error=0.5, error_pct=25.0),
            dict(case='bump', seed=0, survived=True, state='home', error=0.04, error_pct=2.0,
                 speed_at_release=0.001, contacts=1),
            dict(case='bump', seed=1, survived=False, state='aborted', abort_reason='stall',
                 error=0.9, error_pct=45.0, speed_at_release=0.2, contacts=4),
            dict(case='bump', seed=2, failed='no result')]
    lines = table(runs, 3, 5.0).splitlines()
    brief = next(l for l in lines if l.startswith('| brief'))
    bump = next(l for l in lines if l.startswith('| bump'))
    assert brief == '| brief | 2 | 1 (50 %) | 0 | — | 1 | 1.00 (1.00) | 0.020 (0.020) | 0, 1 (home) |'
    assert bump == ('| bump | 3 | 1 (33 %) | 2 | 0.101 (0.200) | 1 | 2.00 (2.00) | 0.040 (0.040) | '
                    '0, 1 (stall), 2 (no result) |')


def test_logged_contacts_counts_the_servers_contact_lines(tmp_path):
    from blind_navigation.evaluation.survival import logged_contacts
    log = tmp_path / 'launch.log'
    log.write_text('[WARN] back_travel_server: goal 9: bumper contact 1 (bumper center pressed): holding\n'
                   '[ERROR] SAFETY STOP: bumper center pressed\n'
                   '[WARN] back_travel_server: goal 11: bumper contact 2 (bumper left pressed): holding\n')
    assert logged_contacts(str(log)) == 2


def test_the_docking_row_counts_missions_from_the_dock(tmp_path):
    from blind_navigation.evaluation import docking
    text, rows = docking.section(2, 4000, ('kinematic',), 1, str(tmp_path), log=lambda _: None)
    assert len(rows) == 2 and {r['base'] for r in rows} == {'kinematic'}
    assert all(5.0 <= r['length'] <= 31.0 and r['state'] in ('docked', 'home') for r in rows), rows
    assert all(r['docked'] == (r['state'] == 'docked') for r in rows), rows
    assert '| kinematic | 2 |' in text and os.path.exists(str(tmp_path / 'docking.csv'))

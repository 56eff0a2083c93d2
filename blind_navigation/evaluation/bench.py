"""`make bench`: the whole evaluation, written to results/ (Markdown, CSV, PNG, TUM, bags).

    /usr/bin/python3 -m blind_navigation.evaluation.bench [--seeds 20] [--processes 2]
        [--real-like-paths 60] [--real-like-seed 1000] [--no-real-like-events]
        [--loops-paths 40] [--loops-seed 2000] [--physics-paths 100] [--physics-table6-seeds 3]
        [--physics-trajectory-seeds 2] [--physics-loop-paths 12] [--docking-paths 20]
        [--no-ros] [--ros-seeds 2] [--rtf 4]
        [--ros-harness-seeds 2] [--ros-harness-rtf 5] [--ros-harness-rtf1-runs 3]
        [--ros-set 10] [--ros-set-bases kinematic mujoco]
        [--no-cost] [--cost-reps 3] [--cost-latency-seeds 3] [--survival-seeds 5]
        [--survival-rtf 5] [--only-survival]
        [--out results]

Sections (docs/evaluation.md says what each number means):
1. Tables III-VI re-measured on the plain-Python harness (paper profile, every
   control mode, --seeds seeds), paper's values beside ours;
2. reconstruction: adaptive two-rate vs uniform sampling at the same count;
3. storage: landmark file vs a rosbag of /odom (harness, real bags);
4. TUM trajectories and the figures;
5. real-like paths (evaluation/real_like.py): seeded random paths per category
   and replayed real trajectories, every mode, error against the physical floor;
6. loops (evaluation/loops.py): paths that come back to where they have been,
   the closed-loop return pruned and unpruned: return length, time and error;
7. physics base (evaluation/physics.py): the default launch on the MuJoCo Kobuki
   (sim/mujoco_kobuki.py) beside the kinematic one, same missions and seeds;
7b. docking (evaluation/docking.py): seeded 5-30 m missions from the Kobuki's dock with
   dock_at_home, both bases: how many end docked, the time from home to docked;
8. ROS runs (bench.launch): ROS vs harness on the same missions and seeds,
   the landmark file vs the bag of the same run, detection and rotation latency,
   and run by run on real trajectories and real-like paths (evaluation/ros_harness.py),
   issue 29's seeded set on both bases (ros_harness.run_set);
9. the layer's running cost in real time (evaluation/cost.py, launch/cost.launch):
   CPU and peak RSS per process at rtf 1 beside ``rosbag record /odom``, the
   default launch and the paper's layout, while recording and during the
   return; detection latency of the default and the image-based detectors;
10. recovery survival (evaluation/survival.py, bench.launch): a brief vision loss
   mid-mission and a bump mid-return, over seeds: survival % and home error.
"""
import argparse
import os
import shutil
import sys
import time

from ..core.back_travel import MODES
from ..sim.mission import load_mission
from . import cost, docking, loops, paper, physics, plots, real_like, survival, tables
from .storage import write_odom_bag
from .forward import record_forward
from .montecarlo import jobs_for, recording_settings, run_jobs
from .reconstruction import compare_sampling, rebuild_path
from .report import group, markdown_table, med_range, med_worst, median, num, write_csv
from .tum import forward_trajectories, write_tum

TABLE3 = sorted(paper.TABLE3)
TABLE5 = sorted(paper.TABLE5)
TABLE6 = sorted(paper.TABLE6)
ROS_AGREEMENT = [(m, mode) for m in ('table6_test1', 'table6_test3') for mode in ('time', 'closed_loop')]
LATENCY_MISSION = 'table3_test5'
DETECTORS = ('dark', 'stall', 'lost')
SURVIVAL_TITLE = 'Recovery survival: a brief vision loss and a bump (ROS runs, evaluation/survival.py)'
COST_TITLE = ('The layer\'s running cost: real time, beside `rosbag record /odom` '
              '(evaluation/cost.py, docs/cost.md)')


def log(message):
    print('bench: %s' % message, flush=True)


def _of(rows, prefix):
    return [r for r in rows if r['mission'].startswith(prefix)]


# --------------------------------------------------------------- sections
def montecarlo(args):
    missions = TABLE3 + TABLE5 + TABLE6
    jobs = jobs_for(missions, range(args.seeds), 'paper', MODES)
    started = time.time()
    rows = run_jobs(jobs, args.processes,
                    lambda done, total: log('Monte-Carlo %d/%d jobs (%.0f s)' % (done, total, time.time() - started))
                    if done % 20 == 0 or done == total else None)
    write_csv(os.path.join(args.out, 'montecarlo.csv'), rows)
    return rows


def _reconstruction_job(job):
    mission, profile, seed = job
    out = compare_sampling(mission, profile, seed)
    return [dict(out[kind], mission=mission, profile=profile, seed=seed, sampling=kind)
            for kind in ('adaptive', 'uniform')]


def reconstruction(args):
    jobs = [(m, 'paper', s) for m in TABLE5 + TABLE6 for s in range(args.seeds)]
    jobs += [(m, 'ideal', 0) for m in TABLE5 + TABLE6]
    if args.processes > 1:
        import multiprocessing
        with multiprocessing.Pool(args.processes) as pool:
            rows = [r for job_rows in pool.map(_reconstruction_job, jobs) for r in job_rows]
    else:
        rows = [r for job in jobs for r in _reconstruction_job(job)]
    write_csv(os.path.join(args.out, 'reconstruction.csv'), rows)
    lines = []
    for (mission, profile), runs in group(rows, 'mission', 'profile').items():
        by = {k[0]: v for k, v in group(runs, 'sampling').items()}
        a, u = by['adaptive'], by['uniform']
        lines.append([mission, profile, len(a), '%s / %s' % (num(median([r['samples'] for r in a]), 0),
                                                             num(median([r['samples'] for r in u]), 0)),
                      num(median([r['period'] for r in u]), 2)]
                     + ['%s / %s' % (med_worst([r[key] * 100 for r in a], 1), med_worst([r[key] * 100 for r in u], 1))
                        for key in ('truth_mean', 'truth_max', 'odom_mean', 'odom_max')])
    return markdown_table(['mission', 'profile', 'seeds', 'samples (adaptive / uniform)', 'uniform period s',
                           'mean dev. from truth cm (adaptive / uniform)', 'max dev. from truth cm',
                           'mean dev. from odometry cm', 'max dev. from odometry cm'], lines), rows


def storage_and_tum(args):
    """Landmark file vs a real rosbag of /odom (50 Hz), and TUM files, Table VI seed 0,
    recorded in the paper's configuration (as the paper's memory column)."""
    bag_dir = os.path.join(args.out, 'storage')
    os.makedirs(bag_dir, exist_ok=True)
    lines, rows = [], []
    for mission in TABLE6:
        forward = record_forward(mission, 'paper', 0, **recording_settings('time'))
        bag_bytes = write_odom_bag(os.path.join(bag_dir, '%s_odom.bag' % mission), forward)
        length = sum(lm.d for lm in forward.landmarks)
        p = paper.TABLE6[mission]
        paper_per_m = p['kb'] * 1024.0 / p['distance']
        rows.append({'mission': mission, 'length': length, 'landmarks': len(forward.landmarks),
                     'landmark_bytes': forward.bytes, 'bag_bytes': bag_bytes,
                     'odom_messages': len(forward.odometry), 'paper_kb': p['kb']})
        lines.append([mission, num(length, 2), len(forward.landmarks), forward.bytes,
                      num(forward.bytes / length, 0), bag_bytes, num(bag_bytes / length, 0),
                      num(bag_bytes / float(forward.bytes), 0), '%d KB / %.1f m' % (p['kb'], p['distance']),
                      num(paper_per_m, 0)])
        rebuilt = rebuild_path(forward.landmarks, forward.anchor)
        for kind, poses in forward_trajectories(forward, rebuilt).items():
            write_tum(os.path.join(args.out, 'trajectories', mission, '%s.tum' % kind), poses)
    write_csv(os.path.join(args.out, 'storage.csv'), rows)
    return markdown_table(['mission (seed 0)', 'length m', 'landmarks', 'landmark file B', 'B/m',
                           'rosbag /odom B', 'bag B/m', 'bag / landmarks', 'paper memory',
                           'paper B/m (KB = 1024 B)'], lines)


def figures(args, rows):
    out = {}
    seed0 = [r for r in rows if r['seed'] == 0 and 'forward_path' in r]

    def panels(missions):
        result = []
        for mission in missions:
            runs = [r for r in seed0 if r['mission'] == mission]
            if runs:
                world = load_mission(mission).world or {}
                obstacles = [(o['x'], o['y'], o['radius']) for o in world.get('obstacles', [])]
                result.append(('%s (seed 0): %s' % (mission, ', '.join(
                    '%s %.2f m' % (r['mode'], r['error']) for r in runs)),
                    runs[0]['forward_path'], {r['mode']: r['return_path'] for r in runs}, obstacles))
        return result
    out['fig12'] = plots.forward_return(
        panels(['table3_test1', 'table3_test4']), os.path.join(args.out, 'fig12_straight.png'),
        'Like the paper\'s Figure 12: straight line, forward vs back travel (ground truth)')
    out['fig13'] = plots.forward_return(
        panels(TABLE5), os.path.join(args.out, 'fig13_curved.png'),
        'Like the paper\'s Figure 13: curved paths around an obstacle (grey; the harness has no collisions)')
    out['error'] = plots.error_vs_length(
        _of(rows, 'table6'), [(p['distance'], p['error']) for p in paper.TABLE6.values()],
        os.path.join(args.out, 'error_vs_length.png'),
        'Table VI missions, paper noise profile, %d seeds per point' % args.seeds)
    shutil.copyfile(out['error'], os.path.join(args.out, 'headline.png'))
    return out


def real_like_section(args):
    """Real-like paths (evaluation/real_like.py): the table and the rows."""
    jobs = real_like.jobs_for(args.real_like_paths, args.real_like_seed, args.real_like_trajectory_seeds,
                              not args.no_real_like_events)
    started = time.time()
    rows = real_like.run_jobs(jobs, args.processes,
                              lambda done, total: log('real-like paths %d/%d missions (%.0f s)'
                                                      % (done, total, time.time() - started))
                              if done % 20 == 0 or done == total else None)
    write_csv(os.path.join(args.out, 'real_like.csv'), rows)
    text = ('%d seeded random paths (seeds %d..%d, %s) and the real trajectories of config/paths '
            '(%d seeds each), paper noise profile.\n\n%s\n%s'
            % (args.real_like_paths, args.real_like_seed, args.real_like_seed + args.real_like_paths - 1,
               ', '.join(sorted(real_like.CATEGORIES)), args.real_like_trajectory_seeds,
               real_like.table(rows), real_like.NOTE))
    return text, rows


def loops_section(args):
    """Loops (evaluation/loops.py): the table, the targets and the rows."""
    started = time.time()
    rows = loops.run(args.loops_paths, args.loops_seed, 1, args.processes,
                     lambda done, total: log('loops %d/%d missions (%.0f s)' % (done, total, time.time() - started))
                     if done % 20 == 0 or done == total else None)
    write_csv(os.path.join(args.out, 'loops.csv'), rows)
    text = ('%d seeded loop paths (seeds %d..%d, %s) and the real trajectories of config/paths (1 seed '
            'each), paper noise profile, each returned unpruned and pruned.\n\n%s\n%s\n**Targets** (issue 15, '
            'loop paths): %s\n' % (args.loops_paths, args.loops_seed, args.loops_seed + args.loops_paths - 1,
                                   ', '.join(sorted(loops.LOOP_CATEGORIES)), loops.table(rows), loops.NOTE,
                                   loops.verdict(rows)[0]))
    return text, rows


# --------------------------------------------------------------- ROS runs
def ros_section(args, mc_rows):
    from .ros_runs import calibrate_ros, run_ros
    runs, ros_dir = [], os.path.join(args.out, 'ros')
    calibrations = {}
    for seed in range(args.ros_seeds):
        log('ROS gyro calibration for seed %d (fake_gyro_calibration.launch)' % seed)
        calibrations[seed] = calibrate_ros(ros_dir, seed) or ''
        if not calibrations[seed]:
            log('ROS gyro calibration for seed %d failed: the runs go without it' % seed)
    for mission, mode in ROS_AGREEMENT:
        for seed in range(args.ros_seeds):
            log('ROS run %s %s seed %d (rtf %g)' % (mission, mode, seed, args.rtf))
            runs.append(run_ros(ros_dir, mission, mode, seed, args.rtf,
                                gyro_calibration_file=calibrations[seed]))
    for detector in DETECTORS:
        log('ROS latency run %s, vision failure %s (rtf %g)' % (LATENCY_MISSION, detector, args.latency_rtf))
        runs.append(run_ros(ros_dir, LATENCY_MISSION, 'closed_loop', 0, args.latency_rtf, detector,
                            gyro_calibration_file=calibrations.get(0, '')))
    write_csv(os.path.join(args.out, 'ros_runs.csv'), runs,
              ['mission', 'mode', 'seed', 'vision_failure', 'rtf_requested', 'rtf', 'state', 'failed',
               'length', 'samples', 'stationary_samples', 'bytes', 'error', 'detector',
               'failure_to_trigger', 'trigger_to_rotation', 'behind_real_time', 'abort_reason', 'wall_s'])
    ok = [r for r in runs if 'failed' not in r]
    failed = [r for r in runs if 'failed' in r]
    text = ''
    if failed:
        text += '**Failed ROS runs:** ' + '; '.join(
            '%s %s seed %s: %s' % (r['mission'], r['mode'], r['seed'], r['failed']) for r in failed) + '\n\n'
    text += '### ROS vs plain-Python harness (same missions, modes, seeds; paper profile)\n\n'
    text += agreement_table(ok, mc_rows)
    text += '\n### On disk: the landmark file vs `rosbag record /odom` of the same run\n\n'
    text += disk_table(ok)
    text += '\n### Latency (sim time, ROS runs on the fake TurtleBot)\n\n'
    text += latency_table(ok)
    if args.ros_harness_seeds > 0:
        from . import ros_harness
        rows = ros_harness.run(os.path.join(args.out, 'ros_harness'), args.ros_harness_rtf,
                               args.ros_harness_seeds, args.ros_harness_rtf1_runs, log)
        text += ('\n### ROS beside the harness run by run: real trajectories and real-like paths '
                 '(evaluation/ros_harness.py)\n\n' + ros_harness.table(rows, args.ros_harness_rtf)
                 + ros_harness.NOTE)
    if args.ros_set > 0:
        from . import ros_harness
        rows = ros_harness.run_set(os.path.join(args.out, 'ros_set'), args.ros_set_bases, args.ros_set,
                                   args.ros_harness_rtf, ((15.0, 2), (1.0, 2)), log=log)
        text += ('\n### Issue 29: seeded real-like paths 5-40 m over ROS beside the harness, each base '
                 '(evaluation/ros_harness.run_set)\n\n' + ros_harness.set_table(rows, args.ros_harness_rtf))
    return text, runs


def survival_section(args):
    """Recovery survival (evaluation/survival.py): writes survival.md; its text."""
    text, _ = survival.section(args.out, args.survival_seeds, args.survival_rtf, log)
    with open(os.path.join(args.out, 'survival.md'), 'w') as stream:
        stream.write('## %s\n\n%s' % (SURVIVAL_TITLE, text))
    log('wrote %s' % os.path.join(args.out, 'survival.md'))
    return text


def agreement_table(ros, mc_rows):
    harness = {(r['mission'], r['mode'], r['seed']): r for r in mc_rows}
    lines = []
    for r in ros:
        if r['vision_failure'] != 'dark' or r['mission'] == LATENCY_MISSION:
            continue
        h = harness.get((r['mission'], r['mode'], r['seed']))
        moving = r['samples'] - (r['stationary_samples'] or 0)
        lines.append([r['mission'], r['mode'], r['seed'], r['state'],
                      '%d (+%d before the start)' % (moving, r['stationary_samples'] or 0),
                      h['samples'] if h else '—', num(r['length'], 2), num(h['length'], 2) if h else '—',
                      num(r['error']), num(h['error']) if h else '—', num(r['rtf'], 1),
                      r.get('behind_real_time', '—'), r.get('abort_reason') or ''])
    table = markdown_table(['mission', 'mode', 'seed', 'ROS state', 'ROS samples', 'harness samples',
                            'ROS length m', 'harness length m', 'ROS error m', 'harness error m',
                            'achieved rtf', '"behind real time" logs', 'abort reason'], lines)
    summary = []
    for (mission, mode), runs in group([r for r in ros if r['vision_failure'] == 'dark'
                                        and r['mission'] != LATENCY_MISSION], 'mission', 'mode').items():
        same = [harness[(mission, mode, r['seed'])] for r in runs if (mission, mode, r['seed']) in harness]
        every = [h for h in mc_rows if h['mission'] == mission and h['mode'] == mode]
        summary.append([mission, mode, len(runs), med_range([r['error'] for r in runs]),
                        med_range([h['error'] for h in same]), '%s (%d seeds)' % (
                            med_range([h['error'] for h in every]), len(every))])
    table += '\nPosition error m, median [min..max]:\n\n' + markdown_table(
        ['mission', 'mode', 'ROS runs', 'ROS', 'harness, same seeds', 'harness, all Monte-Carlo seeds'], summary)
    return table


def disk_table(ros):
    """The landmark file against the bag of /odom recorded beside the layer (what the layer
    costs to run is measured in real time by the cost section, evaluation/cost.py)."""
    disk = []
    for r in ros:
        if r.get('bag') and r.get('length'):
            disk.append([r['mission'], r['mode'], r['seed'], num(r['rtf'], 1), r['bytes'],
                         num(r['bytes'] / r['length'], 0), r['bag']['bytes'], r['bag']['messages'],
                         num(r['bag']['bytes'] / r['length'], 0), num(r['bag']['bytes'] / float(r['bytes']), 0)])
    if not disk:
        return 'no run recorded a bag\n'
    return ('The bag spans launch to vision loss, the landmark file the layer\'s recording:\n\n'
            + markdown_table(['mission', 'mode', 'seed', 'rtf', 'landmark file B', 'B/m', 'bag B',
                              'bag messages', 'bag B/m', 'bag / landmarks'], disk))


def latency_table(ros):
    lines = []
    for (failure, rtf), runs in group(ros, 'vision_failure', 'rtf_requested').items():
        lines.append([failure, ', '.join(sorted(set(r['detector'] for r in runs))), num(rtf, 0), len(runs),
                      med_range([r['failure_to_trigger'] for r in runs], 2),
                      med_range([r['trigger_to_rotation'] for r in runs], 2)])
    return markdown_table(['vision failure', 'detector that fired', 'rtf', 'runs',
                           'failure -> vision_lost s', 'vision_lost -> first rotation command s'], lines) + (
        '\nWith heading correction (blind_navigation.launch\'s default) the pi turn starts after '
        'its standstill, which measures the gyro bias as long as the mission needs (5 s at '
        'least, 120 s at most: heading_budget), so vision_lost -> first rotation command is that '
        'plus the hand-over; the paper\'s configuration (time) turns at once.\n')


# --------------------------------------------------------------- report
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seeds', type=int, default=20, help='Monte-Carlo seeds per mission (>= 10 for the tables)')
    parser.add_argument('--processes', type=int, default=2)
    parser.add_argument('--real-like-paths', type=int, default=60,
                        help='random paths of the real-like section (spread over the categories; 0: skip)')
    parser.add_argument('--real-like-seed', type=int, default=1000, help='first seed of the real-like paths')
    parser.add_argument('--real-like-trajectory-seeds', type=int, default=2,
                        help='seeds per real trajectory in the real-like section')
    parser.add_argument('--no-real-like-events', action='store_true',
                        help='real-like section without closed_loop+events (the proposed motion-event samples)')
    parser.add_argument('--loops-paths', type=int, default=40,
                        help='loop paths of the loops section (spread over the categories; 0: skip)')
    parser.add_argument('--loops-seed', type=int, default=2000, help='first seed of the loop paths')
    parser.add_argument('--physics-paths', type=int, default=100,
                        help='random real-like paths of the physics-base section (0: skip the section)')
    parser.add_argument('--physics-table6-seeds', type=int, default=3, help='physics base: seeds per Table VI mission')
    parser.add_argument('--physics-trajectory-seeds', type=int, default=2,
                        help='physics base: seeds per real trajectory')
    parser.add_argument('--physics-loop-paths', type=int, default=12, help='physics base: loop paths')
    parser.add_argument('--docking-paths', type=int, default=20,
                        help='missions from the dock per base of the docking section (0: skip)')
    parser.add_argument('--no-ros', action='store_true', help='skip the ROS runs')
    parser.add_argument('--ros-seeds', type=int, default=2)
    parser.add_argument('--rtf', type=float, default=4.0, help='real-time factor of the agreement runs')
    parser.add_argument('--ros-harness-seeds', type=int, default=2,
                        help='seeds per path of the ROS-beside-the-harness runs (evaluation/ros_harness.py; 0: none)')
    parser.add_argument('--ros-harness-rtf', type=float, default=5.0, help='their real-time factor')
    parser.add_argument('--ros-harness-rtf1-runs', type=int, default=3, help='of them, how many also at rtf 1')
    parser.add_argument('--ros-set', type=int, default=10,
                        help='issue 29\'s ROS-beside-harness paths per base (ros_harness.path_set; 0: none)')
    parser.add_argument('--ros-set-bases', nargs='*', default=['kinematic', 'mujoco'], help='their bases')
    parser.add_argument('--latency-rtf', type=float, default=2.0, help='real-time factor of the latency runs')
    parser.add_argument('--no-cost', action='store_true', help='skip the real-time cost section')
    parser.add_argument('--cost-reps', type=int, default=3,
                        help='real-time cost runs of each configuration (evaluation/cost.py)')
    parser.add_argument('--cost-latency-seeds', type=int, default=3,
                        help='seeds of the real-time detection latency runs (0: none)')
    parser.add_argument('--survival-seeds', type=int, default=5,
                        help='seeds per case of the recovery survival section (0: skip; --no-ros skips it too)')
    parser.add_argument('--survival-rtf', type=float, default=5.0, help='real-time factor of the survival runs')
    parser.add_argument('--only-survival', action='store_true', help='run only the recovery survival section')
    parser.add_argument('--out', default='results')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    if args.only_survival:
        survival_section(args)
        return
    started = time.time()
    timings = {}

    def timed(name, function, *a):
        t = time.time()
        value = function(*a)
        timings[name] = time.time() - t
        log('%s done in %.0f s' % (name, timings[name]))
        return value

    rows = timed('Monte-Carlo', montecarlo, args)
    recon_text, _ = timed('reconstruction', reconstruction, args)
    foot_text = timed('storage + TUM', storage_and_tum, args)
    timed('figures', figures, args, rows)
    real_text = ''
    if args.real_like_paths > 0:
        real_text, _ = timed('real-like paths', real_like_section, args)
    loops_text = ''
    if args.loops_paths > 0:
        loops_text, _ = timed('loops', loops_section, args)
    physics_text = ''
    if args.physics_paths > 0:
        physics_text, physics_rows = timed('physics base', physics.section, args, log)
        write_csv(os.path.join(args.out, 'physics.csv'), physics_rows)
    docking_text = ''
    if args.docking_paths > 0:
        docking_text, _ = timed('docking', docking.section, args.docking_paths, 4000, docking.BASES,
                                args.processes, args.out, log)
    ros_text = ''
    if not args.no_ros:
        ros_text, _ = timed('ROS runs', ros_section, args, rows)
        with open(os.path.join(args.out, 'ros.md'), 'w') as stream:
            stream.write('## ROS runs\n\n' + ros_text)
    survival_text = ''
    if not args.no_ros and args.survival_seeds > 0:
        survival_text = timed('recovery survival', survival_section, args)
    cost_text = ''
    if not args.no_cost:
        cost_dir = os.path.join(args.out, 'cost')
        os.makedirs(cost_dir, exist_ok=True)
        cost_text, _ = timed('real-time cost', cost.section, cost_dir, tuple(cost.CONFIGS),
                             args.cost_reps, 6, 10.0, args.cost_latency_seeds)
        with open(os.path.join(args.out, 'cost.md'), 'w') as stream:
            stream.write('## %s\n\n%s' % (COST_TITLE, cost_text))
    sections = [
        ('table_iii', 'Table III: straight lines (paper / ours)', tables.table3(_of(rows, 'table3'))),
        ('table_iv', 'Table IV: back travel on the straight lines, by forward velocity',
         tables.table4(_of(rows, 'table3'))),
        ('table_v', 'Table V: curved paths with obstacles (paper / ours)', tables.table5(_of(rows, 'table5'))),
        ('table_vi', 'Table VI: six paths, samples, memory, position error per mode',
         tables.table6(_of(rows, 'table6'))),
        ('table_vi_recorded', 'Table VI: recorded velocities (paper / ours)',
         tables.table6_recorded(_of(rows, 'table6'))),
        ('reconstruction', 'Reconstruction: adaptive two-rate vs uniform sampling, same sample count', recon_text),
        ('storage', 'Storage: landmark file (paper configuration) vs rosbag of /odom (harness, 50 Hz, real bags)', foot_text),
    ]
    if real_text:
        sections.append(('real_like', 'Real-like paths: random paths per category and real trajectories, '
                         'error against the physical floor', real_text))
    if loops_text:
        sections.append(('loops', 'Loops: the return pruned and unpruned (return length, time and error)',
                         loops_text))
    if physics_text:
        sections.append(('physics', 'Physics base: the MuJoCo Kobuki beside the kinematic one (same missions '
                         'and seeds, default launch)', physics_text))
    if docking_text:
        sections.append(('docking', 'Docking at home: missions from the Kobuki\'s dock with dock_at_home',
                         docking_text))
    note = ('\nRecorded statistics (RLV, RAV, samples, memory) are those of the `time` runs, i.e. the '
            'paper\'s configuration (launch/paper.launch, classifier dead-band 0); `closed_loop` records '
            'with blind_navigation.launch\'s dead-band 0.01 rad (montecarlo.csv has every mode\'s).\n')
    sections = [(slug, title, text + note if slug.startswith('table') else text)
                for slug, title, text in sections]
    headline = tables.headline(_of(rows, 'table6'))
    with open(os.path.join(args.out, 'headline.md'), 'w') as stream:
        stream.write(headline_text(args, headline))
    for slug, title, text in sections:
        with open(os.path.join(args.out, '%s.md' % slug), 'w') as stream:
            stream.write('## %s\n\n%s' % (title, text))
    total = time.time() - started
    with open(os.path.join(args.out, 'report.md'), 'w') as stream:
        stream.write('# blind_navigation evaluation (`make bench`)\n\n')
        stream.write('Generated by `%s`; %d Monte-Carlo seeds per mission, paper noise profile; '
                     'wall time %.0f s (%s). What each number means: docs/evaluation.md.\n\n'
                     % (' '.join(['make bench'] + (argv or sys.argv[1:])), args.seeds, total,
                        ', '.join('%s %.0f s' % kv for kv in timings.items())))
        stream.write('## Headline\n\n' + headline_text(args, headline) + '\n')
        for _, title, text in sections:
            stream.write('## %s\n\n%s\n' % (title, text))
        if ros_text:
            stream.write('## ROS runs\n\n' + ros_text)
        if survival_text:
            stream.write('\n## %s\n\n%s' % (SURVIVAL_TITLE, survival_text))
        if cost_text:
            stream.write('\n## %s\n\n%s' % (COST_TITLE, cost_text))
        stream.write('\nFigures: fig12_straight.png, fig13_curved.png, error_vs_length.png (= headline.png). '
                     'Trajectories (TUM): trajectories/<mission>/{ground_truth,odometry,landmarks}.tum. '
                     'CSV: montecarlo.csv, reconstruction.csv, storage.csv, real_like.csv, loops.csv, '
                     'physics.csv, ros_runs.csv, survival.csv.\n')
    print(open(os.path.join(args.out, 'report.md')).read())
    log('wrote %s/report.md in %.0f s' % (args.out, total))


def headline_text(args, table):
    return ('Position error at the end of back travel (ground truth, m), median (worst) over %d seeds '
            'on the fake TurtleBot with the paper noise profile; `time` is the paper\'s sampled-time '
            'method, `closed_loop` this package\'s default. Regenerate: `make bench`.\n\n%s\n'
            '![error vs path length](headline.png)\n' % (args.seeds, table))


if __name__ == '__main__':
    main()

"""Issue 29's set, the gyro bias measured standing still: over ROS against the harness.

    python3 scripts/bias_check.py estimates OUT [COUNT [FIRST]]   each run of the set in OUT (ros_harness --set
                                          COUNT, first seed FIRST, default 3000, --out OUT): the robot's true bias, the estimate over ROS
                                          and in the harness, each error in its own std; RMS per base
    python3 scripts/bias_check.py forced OUT KEY PATH_SEED NOISE_SEED BASE
                                          the harness on that run with the bias estimate forced
                                          to the ROS run's: how much of the gap the bias explains
"""
import glob
import json
import math
import sys

import yaml

from blind_navigation.core import heading_correction, mission_record
from blind_navigation.evaluation.montecarlo import settings_for
from blind_navigation.evaluation.real_like import mission_of
from blind_navigation.evaluation.ros_harness import path_set
from blind_navigation.sim.harness import run_modes
from blind_navigation.sim.kobuki import load_profile
from blind_navigation.sim.mujoco_kobuki import make_base


def run_dir(out, key, path_seed, seed, base):
    return '%s/%s_p%d_s%d_events_pruned%s/rtf5' % (out, key, path_seed, seed, '' if base == 'kinematic' else '_' + base)


def ros_estimate(directory):
    """(bias, std) the ROS run's heading correction used (its progress file)."""
    progress = glob.glob(directory + '/landmarks/*.progress.yaml')[0]
    with open(progress) as stream:
        correction = yaml.safe_load(stream)['route']['heading']['correction']
    return correction[0], correction[2]


def harness(key, path_seed, seed, base):
    """The harness's closed_loop result of the run (the set's settings)."""
    launched = settings_for('paper', seed, base)
    return run_modes(mission_of(key, key, path_seed), 'paper', ('closed_loop',), seed, settings_of=lambda mode: dict(
        launched(mode), event_sampling=True, prune_loops=True))['closed_loop']


def estimates(out, count, first=3000):
    for base in ('kinematic', 'mujoco'):
        errors = {'ROS': [], 'harness': []}
        for index, (_, key, path_seed) in enumerate(path_set(count, first)):
            seed = first + index
            if not glob.glob(run_dir(out, key, path_seed, seed, base)):
                continue
            true_bias = make_base(base, load_profile('paper'), seed=seed)._gyro_bias
            ros, ros_std = ros_estimate(run_dir(out, key, path_seed, seed, base))
            own = harness(key, path_seed, seed, base).heading_correction
            errors['ROS'].append((ros - true_bias) / ros_std)
            errors['harness'].append((own.bias - true_bias) / own.bias_std)
            print('%s %s %d/%d: true %+.2e; ROS %+.2e (%+.1f std); harness %+.2e (%+.1f std)' % (
                base, key, path_seed, seed, true_bias, ros, errors['ROS'][-1], own.bias, errors['harness'][-1]))
        if not errors['ROS']:
            continue
        print('%s: RMS error in its own std: ROS %.2f, harness %.2f' % (base, *(
            math.sqrt(sum(e * e for e in errors[side]) / len(errors[side])) for side in ('ROS', 'harness'))))


def forced(out, key, path_seed, seed, base):
    directory = run_dir(out, key, path_seed, seed, base)
    bias = ros_estimate(directory)[0]
    with open(directory + '/probe.json') as stream:
        probe = json.load(stream)
    own = harness(key, path_seed, seed, base)
    estimate = heading_correction.estimate_correction
    mission_record.estimate_correction = lambda *args, **kwargs: estimate(*args, **kwargs)._replace(bias=bias)
    try:
        with_ros = harness(key, path_seed, seed, base)
    finally:
        mission_record.estimate_correction = estimate
    print('%s %s %d/%d: harness %.2f %% (bias %.2e); with the ROS run\'s bias %.2e: %.2f %%; ROS %.2f %%' % (
        base, key, path_seed, seed, 100 * own.position_error / own.distance, own.heading_correction.bias, bias,
        100 * with_ros.position_error / with_ros.distance, 100 * probe['error'] / probe['length']))


if __name__ == '__main__':
    if len(sys.argv) >= 3 and sys.argv[1] == 'estimates':
        estimates(sys.argv[2], *(int(arg) for arg in sys.argv[3:5]))
    elif len(sys.argv) == 7 and sys.argv[1] == 'forced':
        forced(sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5]), sys.argv[6])
    else:
        sys.exit(__doc__)

#!/usr/bin/env python3
"""Re-run the paper's Table III (and a plain time-based Table IV replay) on the simulated Kobuki.

Table III: the operator's mission config/missions/table3_test<i>.yaml at 10 Hz;
the recorded linear velocity (RLV) is /odom's twist sampled every 2 s while the
robot moves. Table IV (indicative only): the same run, then the recorded RLVs
replayed open loop (each for its 2 s, w = 0) after an ideal pi turn; the
back-travel layer's own controller repeats this check with the real nodes.
Usage: calibrate_fake.py [profile] [seeds]
"""
import math
import sys

from blind_navigation.core.geometry import Pose2D
from blind_navigation.core.kobuki import SimulatedKobuki, load_profile
from blind_navigation.core.mission import load_mission

PAPER_III = {0.05: (0.053, 0.036, 12, 37), 0.08: (0.096, 0.066, 15, 23), 0.12: (0.122, 0.083, 3, 17),
             0.2: (0.194, 0.160, 0, 12), 0.25: (0.249, 0.209, 0, 10)}
PAPER_IV_PE = {0.05: 6.93, 0.08: 6.13, 0.12: 7.57, 0.2: 11.93}
SAMPLE_PERIOD, OPERATOR_DT = 2.0, 0.1


def run(profile, seed, test):
    mission = load_mission('table3_test%d' % test)
    base = SimulatedKobuki(profile, seed=seed)
    samples, next_sample = [], SAMPLE_PERIOD
    while True:
        command = mission.command_at(base.t)
        if command is None:
            break
        base.command(*command)
        base.step(OPERATOR_DT)
        if base.t >= next_sample - 1e-9:
            samples.append(base.odom.v)
            next_sample += SAMPLE_PERIOD
    sv = mission.segments[0][0]
    forward = base.true_pose
    base.command(0.0, 0.0)
    base.step(2.0)
    turned = SimulatedKobuki(profile, seed=seed + 1000, start=Pose2D(forward.x, forward.y, math.pi))
    for v in samples:
        for _ in range(int(round(SAMPLE_PERIOD / OPERATOR_DT))):
            turned.command(v, 0.0)
            turned.step(OPERATOR_DT)
    turned.command(0.0, 0.0)
    turned.step(2.0)
    covered = math.hypot(turned.true_pose.x - forward.x, turned.true_pose.y - forward.y)
    distance = math.hypot(forward.x, forward.y)
    return sv, samples, 100.0 * (distance - covered) / distance


def main():
    name = sys.argv[1] if len(sys.argv) > 1 else 'paper'
    seeds = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    profile = load_profile(name)
    print('profile %s, %d seeds; paper value in brackets' % (name, seeds))
    print('SV m/s | RLV max       | RLV min       | samples > SV      | samples | Table IV PE %% (time replay)')
    for test in range(1, 6):
        runs = [run(profile, seed, test) for seed in range(seeds)]
        sv = runs[0][0]
        p_max, p_min, p_over, p_total = PAPER_III[sv]
        rlv_max = sum(max(s) for _, s, _ in runs) / seeds
        rlv_min = sum(min(s[1:]) for _, s, _ in runs) / seeds      # the first sample is the start-up
        over = sum(sum(1 for v in s if v > sv) for _, s, _ in runs) / seeds
        total = sum(len(s) for _, s, _ in runs) / seeds
        pe = sorted(r[2] for r in runs)
        paper_pe = PAPER_IV_PE.get(sv)
        print('%.2f   | %.3f (%.3f) | %.3f (%.3f) | %4.1f of %4.1f (%2d) | %4.1f (%d) | %5.1f [%.1f..%.1f] (%s)'
              % (sv, rlv_max, p_max, rlv_min, p_min, over, total, p_over, total, p_total,
                 sum(pe) / seeds, pe[0], pe[-1], '%.2f' % paper_pe if paper_pe else '-'))


if __name__ == '__main__':
    main()

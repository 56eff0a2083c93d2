"""The recording half of a harness mission, with everything the evaluation reads.

:func:`record_forward` runs the harness's own recording step on a robot that also logs
the landmarks, the 50 Hz odometry and the timed ground truth, so it is the same forward
run as ``sim.harness.run_mission``'s for the same mission, profile, seed and settings.
"""
import os
import tempfile
from collections import namedtuple

from ..sim import harness as simulation
from ..sim.kobuki import load_profile, make_profile
from ..sim.mission import load_mission

ForwardRecord = namedtuple('ForwardRecord', [
    'mission', 'landmarks', 'bytes', 'anchor', 'odometry', 'truth', 'duration'])
ForwardRecord.__doc__ = (
    'Forward part of one mission: landmarks (as loaded from the written store), '
    'bytes of the store, anchor (odometry x, y where recording stopped), '
    'odometry [OdomState] and truth [(t, Pose2D)] at every control step, duration (s).')


class _LoggedRun(simulation._Run):
    """The harness's robot, also logging odometry and the true pose every step."""

    def __init__(self, profile, seed, dt):
        super(_LoggedRun, self).__init__(profile, seed, dt)
        self.odometry, self.truth = [], []

    def advance(self, command=None):
        super(_LoggedRun, self).advance(command)
        self.odometry.append(self.base.odom)
        self.truth.append((self.base.t, self.base.true_pose))


def harness_settings(**overrides):
    """The harness settings (simulation.SIMULATION_DEFAULTS) with ``overrides``."""
    unknown = set(overrides) - set(simulation.SIMULATION_DEFAULTS)
    if unknown:
        raise ValueError('unknown harness settings: %s' % ', '.join(sorted(unknown)))
    return dict(simulation.SIMULATION_DEFAULTS, **overrides)


def record_forward(mission, profile='paper', seed=0, **settings):
    """Record ``mission`` as run_mission does; returns a :class:`ForwardRecord`."""
    settings = harness_settings(**settings)
    mission = load_mission(mission) if isinstance(mission, str) else mission
    profile = load_profile(profile) if isinstance(profile, str) else make_profile(profile)
    run = _LoggedRun(profile, seed, settings['control_dt'])
    with tempfile.TemporaryDirectory() as directory:
        store = os.path.join(directory, 'landmarks.yaml')
        loaded, anchor = simulation._record(run, mission, settings, store)
        size = os.path.getsize(store)
    return ForwardRecord(mission.name, loaded.landmarks, size, anchor, run.odometry, run.truth,
                         run.base.t)

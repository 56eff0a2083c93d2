"""Monte-Carlo runs of the paper's missions on the plain-Python harness.

One job = one mission and seed: ``sim.harness.run_modes`` runs every mode in its launch
configuration (:func:`recording_settings`) and the floor; one row of plain numbers per
mode; :func:`run_jobs` spreads jobs over processes.
"""
import math
import multiprocessing

from ..core.back_travel import MODES
from ..core.geometry import distance, wrap_angle
from ..sim.mission import load_mission
from ..sim.harness import run_modes, simulate_gyro_calibration
from .forward import harness_settings


#: Modes launched in the paper's configuration (launch/paper.launch: the paper's
#: classifier rule without a dead-band, no heading correction); the others run
#: blind_navigation.launch's dead-band and heading correction (with a gyro
#: calibration); the harness's defaults otherwise (no motion events, no pruning).
PAPER_CONFIGURATION_MODES = ('time', 'distance')
#: The gyro calibration used with seed s is made on seed s + this: another
#: power-up (gyro bias) and another visual-odometry drift of the same robot.
CALIBRATION_SEED_OFFSET = 10000


def recording_settings(mode):
    """Harness settings of the configuration ``mode`` is launched with."""
    return {'deadband': 0.0, 'heading_correction': False} if mode in PAPER_CONFIGURATION_MODES else {}


def gyro_calibration_for(profile, seed, base='kinematic'):
    """The gyro calibration (calibrate_gyro.launch, simulated) the user of the
    robot of ``profile`` (on ``base``, sim/mujoco_kobuki.BASES) made before mission ``seed``."""
    return simulate_gyro_calibration(profile, seed + CALIBRATION_SEED_OFFSET, base=base)


def set_velocities(mission):
    """(largest |v| m/s, largest |w| rad/s) the operator commands in ``mission``."""
    return (max(abs(v) for v, _, _ in mission.segments),
            max(abs(w) for _, w, _ in mission.segments))


def landmark_stats(landmarks, sv, asv, settle_time, curved_period=1.0):
    """The paper's recorded-velocity statistics of one recorded path.

    RLV = recorded linear velocity (landmark v), RAV = recorded angular
    velocity (w). ``rlv_min`` counts only landmarks taken while the operator
    drove: tick time (the sum of T) after the first tick (the robot starting)
    and up to the recording's end minus ``settle_time`` (the harness records
    ``settle_time`` s after the operator's last command; the final landmark is
    at vision loss); the maxima and counts use every landmark. ``over`` counts RLV > ``sv``,
    ``rav_over`` |RAV| > ``asv`` (when asv > 0), ``curved`` landmarks taken at
    the curved period.
    """
    if not landmarks:
        raise ValueError('landmark_stats: no landmarks')
    v = [lm.v for lm in landmarks]
    w = [lm.w for lm in landmarks]
    ticks, elapsed = [], 0.0
    for lm in landmarks:
        elapsed += lm.T
        ticks.append(elapsed)
    operator_end = ticks[-1] - settle_time
    moving = [x for x, t in zip(v, ticks) if ticks[0] < t <= operator_end + 1e-6] or v
    return {
        'rlv_max': max(v), 'rlv_min': min(moving), 'over': sum(x > sv + 1e-9 for x in v),
        'rav_max': max(w), 'rav_min': min(w),
        'rav_over': sum(abs(x) > asv + 1e-9 for x in w) if asv > 0 else 0,
        'curved': sum(abs(lm.T - curved_period) < 1e-6 for lm in landmarks),
    }


def return_geometry(forward_path, return_path):
    """Table IV's quantities from the ground-truth paths (start at the origin,
    heading 0): D = start -> where the forward run stopped, its direction HD;
    CD = turn point -> where the return stopped, its direction back HD
    (relative to the reversed forward heading, so 0 = straight back);
    PE % = 100 (D - CD) / D; RM = D - CD. Directions are of the displacement
    (the harness does not return the final true yaw)."""
    (x0, y0), (xt, yt) = forward_path[0], forward_path[-1]
    (xr, yr) = return_path[-1] if return_path else (xt, yt)
    d = distance(x0, y0, xt, yt)
    cd = distance(xt, yt, xr, yr)
    hd = math.atan2(yt - y0, xt - x0)
    back_hd = wrap_angle(math.atan2(yr - yt, xr - xt) - math.pi - hd) if cd > 1e-9 else 0.0
    return {'d': d, 'hd': hd, 'cd': cd, 'back_hd': back_hd,
            'pe': 100.0 * (d - cd) / d if d > 0 else float('nan'), 'rm': d - cd}


def settings_for(profile, seed, base='kinematic'):
    """``settings_of(mode)``: the harness settings ``mode`` is launched with
    (:func:`recording_settings`) on ``base``, with the gyro calibration of this robot
    (:func:`gyro_calibration_for`, made once) where the heading correction runs."""
    calibration = []

    def settings_of(mode):
        settings = dict(recording_settings(mode), base=base)
        if harness_settings(**settings)['heading_correction']:
            if not calibration:
                calibration.append(gyro_calibration_for(profile, seed, base))
            settings['gyro_calibration'] = calibration[0]
        return settings
    return settings_of


def run_job(job):
    """One (mission, profile, seed, modes, keep_paths) job -> list of row dicts. The
    modes of one launch configuration share the recording (sim/harness.run_modes)."""
    mission_name, profile, seed, modes, keep_paths = job
    mission = load_mission(mission_name)
    sv, asv = set_velocities(mission)
    settings_of = settings_for(profile, seed)
    results = run_modes(mission, profile, modes, seed, settings_of=settings_of)
    rows = []
    for mode in modes:
        result = results[mode]
        row = {'mission': mission_name, 'profile': profile, 'mode': mode, 'seed': seed,
               'sv': sv, 'asv': asv, 'status': result.status, 'reason': result.reason,
               'length': result.distance, 'samples': result.samples, 'bytes': result.bytes,
               'error': result.position_error, 'odom_error': result.odom_error,
               'floor': result.floor_error, 'duration': result.duration}
        row['error_pct'] = 100.0 * result.position_error / result.distance if result.distance else float('nan')
        row['deadband'] = harness_settings(**settings_of(mode))['deadband']
        row.update(landmark_stats(result.landmarks, sv, asv, harness_settings()['settle_time']))
        row.update(return_geometry(result.forward_path, result.return_path))
        if keep_paths:
            row['forward_path'] = result.forward_path
            row['return_path'] = result.return_path
        rows.append(row)
    return rows


def jobs_for(missions, seeds, profile='paper', modes=MODES, keep_paths_seed=0):
    """Jobs for every mission and seed; paths kept for seed ``keep_paths_seed``."""
    return [(m, profile, s, tuple(modes), s == keep_paths_seed) for m in missions for s in seeds]


def run_jobs(jobs, processes=2, progress=None, job=None):
    """Rows of ``job`` (default :func:`run_job`) over ``jobs`` on ``processes`` processes,
    in the jobs' order; ``progress(done, total)`` after each job."""
    job = job or run_job
    rows = []
    pool = multiprocessing.Pool(processes) if processes > 1 else None
    results = pool.imap(job, jobs) if pool else map(job, jobs)
    try:
        for index, job_rows in enumerate(results):
            rows.extend(job_rows)
            if progress:
                progress(index + 1, len(jobs))
    finally:
        if pool:
            pool.close()
            pool.join()
    return rows

"""The paper's Tables III-VI, paper's values beside ours, from Monte-Carlo rows
(:mod:`.montecarlo`). Ours are over seeds: 'median [min..max]' for what was
recorded, 'median (worst)' for errors. Each function returns Markdown."""
from . import paper
from .report import farthest_from_zero, group, markdown_table, med_range, med_worst, num

MODE_LABELS = {'time': 'time (paper)', 'distance': 'distance (paper)', 'closed_loop': 'closed_loop'}


def _recorded(rows):
    """Rows of one mode per seed: the forward statistics do not depend on the mode."""
    first = rows[0]['mode']
    return [r for r in rows if r['mode'] == first]


def _col(rows, key):
    return [r[key] for r in rows]


def _seeds(rows):
    return len(_recorded(rows))


def _kb(rows):
    return [r['bytes'] / 1024.0 for r in rows]


def table3(rows):
    """Table III: straight lines at SV 0.05-0.25 m/s; recorded velocities and samples."""
    lines = []
    for (mission,), runs in group(rows, 'mission').items():
        p, rec = paper.TABLE3.get(mission), _recorded(runs)
        if p is None:
            continue
        lines.append([mission, num(p['sv'], 2),
                      '%s / %s' % (num(p['distance']), med_range(_col(rec, 'length'))),
                      '%s / %s' % (num(p['rlv_max']), med_range(_col(rec, 'rlv_max'))),
                      '%s / %s' % (num(p['rlv_min']), med_range(_col(rec, 'rlv_min'))),
                      '%d / %s' % (p['over'], med_range(_col(rec, 'over'), 0)),
                      '%d / %s' % (p['samples'], med_range(_col(rec, 'samples'), 0)),
                      med_range(_col(rec, 'curved'), 0), len(rec)])
    return markdown_table(['mission', 'SV m/s', 'distance m (paper / ours, odometry)',
                           'RLV max m/s', 'RLV min m/s', 'RLV samples > SV', 'total samples',
                           'ours at the curved rate', 'seeds'], lines)


def table4(rows):
    """Table IV: straight back travel by forward velocity, paper row then each mode."""
    lines = []
    for (mission,), runs in group(rows, 'mission').items():
        p = paper.table4_row(mission)
        sv = runs[0]['sv']
        if p is not None:
            lines.append([num(sv, 2), 'paper (FV %.3f, v only)' % p['fv'], num(p['d']), num(p['hd'], 4),
                          num(p['cd']), num(p['back_hd'], 4), num(p['pe'], 2), num(p['rm']), '—'])
        for (mode,), mode_runs in group(runs, 'mode').items():
            lines.append([num(sv, 2), MODE_LABELS.get(mode, mode), med_range(_col(mode_runs, 'd')),
                          med_range(_col(mode_runs, 'hd'), 4), med_range(_col(mode_runs, 'cd')),
                          med_range(_col(mode_runs, 'back_hd'), 4),
                          med_worst(_col(mode_runs, 'pe'), 2, farthest_from_zero),
                          med_worst(_col(mode_runs, 'rm'), 3, farthest_from_zero),
                          med_worst(_col(mode_runs, 'error'))])
    return markdown_table(['SV m/s', 'source', 'D m', 'HD rad', 'CD m', 'back HD rad', 'PE %',
                           'RM m', 'position error m'], lines)


def table5(rows):
    """Table V: curved paths around an obstacle; recorded velocities, samples, errors."""
    lines = []
    modes = list(group(rows, 'mode'))
    for (mission,), runs in group(rows, 'mission').items():
        p, rec = paper.TABLE5.get(mission), _recorded(runs)
        if p is None:
            continue
        errors = [med_worst(_col(m, 'error')) for m in group(runs, 'mode').values()]
        lines.append([mission, '%s / %s' % (num(p['distance']), med_range(_col(rec, 'length'))),
                      '%s / %s' % (num(p['rlv_max']), med_range(_col(rec, 'rlv_max'))),
                      '%s / %s' % (num(p['rlv_min']), med_range(_col(rec, 'rlv_min'))),
                      '%d / %s' % (p['over'], med_range(_col(rec, 'over'), 0)),
                      '%d / %s' % (p['samples'], med_range(_col(rec, 'samples'), 0))] + errors
                     + [len(rec)])
    return markdown_table(['mission', 'distance m (paper / ours)', 'RLV max m/s', 'RLV min m/s',
                           'RLV samples > SV', 'total samples']
                          + ['error m, %s' % MODE_LABELS.get(m[0], m[0]) for m in modes]
                          + ['seeds'], lines)


def table6(rows):
    """Table VI: six paths 2.6-13.2 m; samples, memory, position error per mode."""
    lines = []
    modes = list(group(rows, 'mode'))
    for (mission,), runs in group(rows, 'mission').items():
        p, rec = paper.TABLE6.get(mission), _recorded(runs)
        if p is None:
            continue
        errors = [med_worst(_col(m, 'error')) for m in group(runs, 'mode').values()]
        lines.append([mission, '%s / %s' % (num(p['distance'], 1), med_range(_col(rec, 'length'), 2)),
                      '%d / %s' % (p['samples'], med_range(_col(rec, 'samples'), 0)),
                      '%d / %s' % (p['kb'], med_range(_kb(rec), 1)),
                      num(p['error'], 2)] + errors + [len(rec)])
    return markdown_table(['mission', 'distance m (paper / ours)', 'samples (paper / ours)',
                           'memory KB (paper / ours)', 'paper error m']
                          + ['error m, %s' % MODE_LABELS.get(m[0], m[0]) for m in modes]
                          + ['seeds'], lines)


def table6_recorded(rows):
    """Table VI's recorded-velocity rows: RLV above LSV, max RLV, RAV range."""
    lines = []
    for (mission,), runs in group(rows, 'mission').items():
        p, rec = paper.TABLE6.get(mission), _recorded(runs)
        if p is None:
            continue
        lines.append([mission, '%d / %s' % (p['over'], med_range(_col(rec, 'over'), 0)),
                      '%s / %s' % (num(p['rlv_max']), med_range(_col(rec, 'rlv_max'))),
                      '%s / %s' % (num(p['rav_max']), med_range(_col(rec, 'rav_max'))),
                      '%s / %s' % (num(p['rav_min']), med_range(_col(rec, 'rav_min'))),
                      '0 / %s' % med_range(_col(rec, 'rav_over'), 0),
                      med_range(_col(rec, 'curved'), 0)])
    return markdown_table(['mission', 'RLV samples > LSV (paper / ours)', 'max RLV m/s',
                           'max RAV rad/s', 'min RAV rad/s', 'RAV samples > ASV',
                           'ours at the curved rate (1 Hz)'], lines)


def headline(rows):
    """The README table: Table VI position error, paper vs the faithful port (time) vs closed_loop."""
    lines = []
    for (mission,), runs in group(rows, 'mission').items():
        p = paper.TABLE6.get(mission)
        if p is None:
            continue
        by_mode = group(runs, 'mode')
        cells = []
        for mode in ('time', 'closed_loop'):
            mode_runs = by_mode.get((mode,), [])
            cells.append(med_worst(_col(mode_runs, 'error'), 2) if mode_runs else '—')
        rec = _recorded(runs)
        lines.append(['%s (%.1f m)' % (mission.replace('table6_', ''), p['distance']),
                      num(p['error'], 2)] + cells
                     + ['%d / %s' % (p['kb'], num(sorted(_kb(rec))[len(rec) // 2], 1))])
    return markdown_table(['Table VI path', 'paper error m', 'ours, time (paper method) m',
                           'ours, closed_loop m', 'memory KB (paper / ours)'], lines)

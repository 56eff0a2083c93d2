"""The bench's figures (matplotlib, Agg): forward vs return ground truth like
the paper's Figures 12-13, and position error vs path length per control mode."""
import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

from .report import group, median  # noqa: E402

MODE_STYLE = {'time': ('tab:red', 'time (paper method)'),
              'distance': ('tab:orange', 'distance (paper method)'),
              'closed_loop': ('tab:blue', 'closed_loop')}


def _mode(mode):
    return MODE_STYLE.get(mode, ('tab:gray', mode))


def forward_return(panels, path, title):
    """One subplot per panel: (label, forward [(x, y)], {mode: return [(x, y)]},
    obstacles [(x, y, radius)]). Solid = forward ground truth, dashed = return
    ground truth (the paper's style), grey discs = obstacles."""
    figure, axes = plt.subplots(len(panels), 1, figsize=(9, 3.2 * len(panels)), squeeze=False)
    for ax, (label, forward, returns, obstacles) in zip(axes[:, 0], panels):
        ax.plot(*zip(*forward), '-', color='black', label='forward (ground truth)')
        for mode, back in returns.items():
            color, name = _mode(mode)
            if back:
                ax.plot(*zip(*back), '--', color=color, label='back travel, %s' % name)
                ax.plot(*back[-1], 'x', color=color)
        ax.plot(*forward[0], 'go', label='start')
        for x, y, radius in obstacles:
            ax.add_patch(plt.Circle((x, y), radius, color='gray', alpha=0.5))
        ax.set_aspect('equal', adjustable='datalim')
        ax.set_xlabel('x [m]')
        ax.set_ylabel('y [m]')
        ax.set_title(label, fontsize=10)
        ax.legend(loc='best', fontsize=7)
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path


def error_vs_length(rows, paper_points, path, title):
    """Median (marker) and worst (bar top) position error vs median path length,
    per mode, and the paper's Table VI points."""
    figure, ax = plt.subplots(figsize=(8, 4.5))
    modes = group(rows, 'mode')
    offsets = {mode: (i - (len(modes) - 1) / 2.0) * 0.12 for i, (mode,) in enumerate(modes)}
    for (mode,), mode_rows in modes.items():
        color, name = _mode(mode)
        xs, meds, lows, highs = [], [], [], []
        for _, runs in group(mode_rows, 'mission').items():
            errors = [r['error'] for r in runs]
            xs.append(median([r['length'] for r in runs]) + offsets[mode])
            meds.append(median(errors))
            lows.append(median(errors) - min(errors))
            highs.append(max(errors) - median(errors))
        ax.errorbar(xs, meds, yerr=[lows, highs], fmt='o-', color=color, capsize=3,
                    label='%s: median, bars min..max' % name)
    if paper_points:
        ax.plot(*zip(*paper_points), 's', color='black', label='paper, Table VI')
    ax.set_xlabel('path length [m]')
    ax.set_ylabel('position error at the end [m]')
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=110)
    plt.close(figure)
    return path

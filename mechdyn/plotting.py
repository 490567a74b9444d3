"""Figures of results: what the engineer of a scene looks at.

A result's figure: speeds, positions and the requested outputs (moments in couplings,
powers) against time, with stop, stick and slip events marked. A sweep's figure: an
output against the swept parameter. Needs matplotlib (extra ``plot``).
"""
from __future__ import annotations

import numpy as np

from mechdyn.errors import MechdynError

__all__ = ["plot_result", "plot_sweep", "pyplot", "dense_series", "finish"]


def pyplot():
    """matplotlib.pyplot on a file back end (Jupyter's inline back end is kept), or a
    clear error naming the extra."""
    try:
        import matplotlib
        backend = matplotlib.get_backend().lower()
        if backend != "agg" and "inline" not in backend:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise MechdynError("plots need matplotlib: pip install 'mechdyn[plot]'") from None
    return plt


def dense_series(result, points=1001, sample=None):
    """Times, states and outputs at the step points and ``points`` even times between
    (from the dense output), so curves are smooth and peaks between steps are found;
    or every ``sample`` seconds exactly."""
    if sample is not None:
        times = result.sample_times(sample)
    elif len(result.t) < 2:
        return result.t, result.y, result.outputs
    else:
        times = np.union1d(np.linspace(result.t[0], result.t[-1], points), result.t)
    outputs = result.outputs_at(times) if result.outputs else result.outputs
    return times, result.trajectory.at(times), outputs


def plot_result(result, path=None, points=400, sample=None, units=None, phases=(),
                title=None):
    """Plot a :class:`~mechdyn.simulate.result.Result` (or a duty cycle's
    :class:`~mechdyn.analyse.cycle_result.CycleResult`); save to ``path`` if given.

    Panels, top down: speeds, positions (a panel per unit and scale, so a small
    coordinate is not flattened by a large one), then the requested outputs a panel per
    kind (moments, forces, powers), each axis labelled with its unit (``units``: other
    units to show, see :class:`mechdyn.display.Display`). Events are thin vertical
    lines labelled in a strip above the axes, clear of the curves; ``phases``
    (``(name, start, end)`` each) are shaded in turn, their boundaries drawn solid and
    their names written across the top of the strip.
    """
    from mechdyn.display import Display, column_units, kind_of
    plt = pyplot()
    shown, si = Display(units), column_units(result)
    shown.check(si)
    n = len(result.coordinates)
    t, states, outputs = dense_series(result, points, sample)

    def curve(label, column, values):
        values, unit = shown.values(column, si[column], values)
        return label, values, unit
    panels = [("speed", [curve(f"d{c}/dt", result.state_names[n + i], states[n + i])
                         for i, c in enumerate(result.coordinates)]),
              ("position", [curve(c, c, states[i])
                            for i, c in enumerate(result.coordinates)])]
    panels = [("velocity" if group[0][2] == shown.unit("", "m/s") and name == "speed"
                else name, group) for name, curves in panels for group in _groups(curves)]
    by_kind = {}
    for label, values in outputs.items():
        kind = kind_of(si[label]) or ("power" if label.startswith("power:") else "output")
        by_kind.setdefault(kind, []).append(curve(label, label, values))
    panels += [(kind, group) for kind, curves in by_kind.items() for group in _groups(curves)]
    fig = plt.figure(figsize=(8, 2.4 * len(panels) + 1.2 + 0.3 * bool(phases)))
    grid = fig.add_gridspec(len(panels) + 1, 1, height_ratios=[0.35 + 0.2 * bool(phases)]
                            + [1] * len(panels))
    strip = fig.add_subplot(grid[0])
    axes = [fig.add_subplot(grid[k + 1], sharex=strip) for k in range(len(panels))]
    for ax, (name, curves) in zip(axes, panels):
        for label, values, _ in curves:
            ax.plot(t, values, label=label)
        unit = curves[0][2]
        ax.set_ylabel(f"{name} [{unit.replace('*', ' ')}]" if unit else name)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    for ax in axes[:-1]:
        ax.tick_params(labelbottom=False)
    _mark_events(strip, axes, result.events, result.t[0], result.t[-1],
                 rows=(0.25, 0.5) if phases else (0.3, 0.65))
    _mark_phases(strip, axes, phases)
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(title or f"{result.mechanism_name} — {result.scene.name} ({result.reason})")
    return finish(fig, path)


def _mark_phases(strip, axes, phases):
    """Shade every other phase, draw the boundaries solid, name the phases on top."""
    for k, (name, start, end) in enumerate(phases):
        for ax in axes:
            if k % 2:
                ax.axvspan(start, end, color="0.93", zorder=-1, lw=0)
            if k:
                ax.axvline(start, color="0.35", lw=1.0, zorder=0)
        if k:
            strip.axvline(start, ymin=0.72, ymax=1.0, color="0.35", lw=1.0)
        strip.text((start + end) / 2, 0.97, name, fontsize=8, fontweight="bold",
                   ha="center", va="top", clip_on=False)


def _groups(curves, ratio=20.0):
    """Curves split by unit, and within a unit by scale (largest magnitudes more than
    ``ratio`` apart go to separate panels)."""
    groups = []
    for unit in dict.fromkeys(u for _, _, u in curves):
        same = sorted((c for c in curves if c[2] == unit),
                      key=lambda c: -float(np.nanmax(np.abs(c[1]), initial=0.0)))
        for curve in same:
            size = float(np.nanmax(np.abs(curve[1]), initial=0.0))
            if groups and groups[-1][0][2] == unit and size * ratio >= groups[-1][0][3]:
                groups[-1].append(curve + (size,))
            else:
                groups.append([curve + (size,)])
    return [[c[:3] for c in group] for group in groups]


def _mark_events(strip, axes, events, t_start, t_end, rows=(0.3, 0.65)):
    """A thin line per event time on every axes (a tick in the strip for repeated
    events); in the strip above them a label per
    event, or per group of an element's repeated events (``slip guide: 83 times, t =
    0.05 ... 3.98 s``), on two rows, each only where it fits (the result's ``events``
    keep them all; a note counts the labels left out)."""
    from mechdyn.display import event_groups
    strip.set_axis_off()
    strip.set_ylim(0, 1)
    span = max(t_end - t_start, 1e-300)
    groups = event_groups(events, t_start, t_end)
    for _, _, times in groups:              # a repeated event: a tick in the strip only
        for time in times:
            for ax in axes if len(times) == 1 else ():
                ax.axvline(time, color="grey", lw=0.6, ls="--", zorder=0)
            strip.axvline(time, ymax=rows[0] - 0.05, color="grey", lw=0.6)
    width = strip.get_position().width * strip.figure.get_figwidth() * 72    # points
    per_char = 0.6 * 7 / width * span                     # time per character at 7 pt
    free = [t_start - span] * len(rows)                   # each row is free from here
    left_out = 0
    for _, label, times in groups:
        size = (len(label) + 2) * per_char
        right = times[0] > t_start + 0.5 * span
        begin = times[0] - size if right else times[0]
        row = next((k for k, after in enumerate(free) if begin >= after and
                    t_start - 0.02 * span <= begin and begin + size <= t_end + 0.02 * span),
                   None)
        if row is None:
            left_out += 1
            continue
        free[row] = begin + size
        strip.text(times[0], rows[row], label, fontsize=7, va="bottom",
                   ha="right" if right else "left", clip_on=False)
    if left_out:
        strip.text(1.0, 0.95, f"+{left_out} event labels left out (result.events)",
                   fontsize=6, ha="right", va="top", transform=strip.transAxes)


def plot_sweep(sweep, y, path=None):
    """Column ``y`` of a :class:`~mechdyn.analyse.sweeps.Sweep` against its first swept
    parameter, a line per combination of the other swept parameters; failed points
    marked on the axis."""
    plt = pyplot()
    x_name, others = sweep.parameters[0], sweep.parameters[1:]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    series = {}
    for row in sweep.rows:
        series.setdefault(tuple(row[o] for o in others), []).append(row)
    for key, rows in series.items():
        rows = sorted(rows, key=lambda r: r[x_name])
        label = ", ".join(f"{o} = {v:.4g}" for o, v in zip(others, key)) or None
        ax.plot([r[x_name] for r in rows], [r[y] for r in rows], marker="o", ms=3,
                label=label)
    failed = [row[x_name] for row in sweep.failed]
    if failed:
        ax.plot(failed, [0] * len(failed), "rx", transform=ax.get_xaxis_transform(),
                clip_on=False, label=f"failed ({len(failed)})")
    ax.set_xlabel(sweep.label(x_name))
    ax.set_ylabel("stop time t_end [s]" if y == "t_end" else sweep.label(y))
    ax.set_title(f"{y} against {x_name} ({len(sweep)} points)")
    ax.grid(True, alpha=0.3)
    if ax.get_legend_handles_labels()[1]:
        ax.legend(fontsize=8)
    return finish(fig, path)


def finish(fig, path):
    """Lay out ``fig``; save it to ``path`` (suffix picks PNG, SVG, PDF) and close it, or
    return it open when there is no path (Jupyter)."""
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
        pyplot().close(fig)
    return fig


def figure_html(fig, alt) -> str:
    """A matplotlib figure as an embedded PNG in a paragraph (the figure is closed)."""
    import base64
    import io
    from mechdyn.tabular import escape
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=100)
    pyplot().close(fig)
    data = base64.b64encode(buffer.getvalue()).decode("ascii")
    return f"<p><img alt='{escape(alt)}' src='data:image/png;base64,{data}'></p>"

"""Figures of results: what the engineer of a scene looks at.

Panels: coordinates, speeds, and the requested outputs (moments in couplings, powers)
against time; stop, stick and slip events marked. Needs matplotlib (extra ``plot``).
"""
from __future__ import annotations

import numpy as np

from .errors import MechdynError

__all__ = ["plot_result", "pyplot"]


def pyplot():
    """matplotlib.pyplot on a file back end, or a clear error naming the extra."""
    try:
        import matplotlib
        matplotlib.use("Agg") if matplotlib.get_backend().lower() != "agg" else None
        import matplotlib.pyplot as plt
    except ImportError:
        raise MechdynError("plots need matplotlib: pip install 'mechdyn[plot]'") from None
    return plt


def plot_result(result, path=None, points=400):
    """Plot a :class:`~mechdyn.result.Result`; save to ``path`` if given."""
    plt = pyplot()
    n = result.compiled.dof
    if len(result.t) > 1:
        dense_t = np.linspace(result.t[0], result.t[-1], points)
        t = np.union1d(dense_t, result.t)
        states = result.trajectory.at(t)
    else:
        t, states = result.t, result.y
    panels = 2 + (1 if result.outputs else 0)
    fig, axes = plt.subplots(panels, 1, sharex=True, figsize=(8, 2.6 * panels + 0.6))
    for i, name in enumerate(result.coordinates):
        unit = result.units.get(name, "rad")
        axes[0].plot(t, states[i], label=f"{name} [{unit}]")
        axes[1].plot(t, states[n + i], label=f"d{name}/dt [{unit}/s]")
    axes[0].set_ylabel("position")
    axes[1].set_ylabel("speed")
    if result.outputs:
        for label, values in result.outputs.items():
            axes[2].plot(result.t, values, label=label)
        axes[2].set_ylabel("outputs")
    for ax in axes:
        for event in result.events:
            if event.kind in ("stick", "slip", "end"):
                ax.axvline(event.time, color="grey", lw=0.8, ls="--")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=8)
    for event in result.events:
        if event.kind in ("stick", "slip", "end"):
            axes[0].annotate(f"{event.kind} {event.name}\nt = {event.time:.4g} s",
                             (event.time, axes[0].get_ylim()[1]), fontsize=7,
                             va="top", ha="right")
    axes[-1].set_xlabel("time t [s]")
    fig.suptitle(f"{result.mechanism_name} — {result.scene.name} ({result.reason})")
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=110)
        plt.close(fig)
    return fig

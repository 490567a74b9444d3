"""Figures engineers draw of a linkage over one crank revolution: transmission
functions, reduced inertia and its slope, the transmission angle, coupler curves; and of
its kinetostatics: joint forces, the driving moment, the shaking force and moment.
Needs matplotlib (extra ``plot``).
"""
from __future__ import annotations

import numpy as np

from mechdyn.analyse.linkage_types import LinkageError
from mechdyn.plotting import finish, pyplot

__all__ = ["revolution", "plot_linkage", "plot_kinetostatics"]


def revolution(linkage, points=361):
    """A sweep over one crank revolution from the current position, or over the
    crank's range on this branch for a crank that cannot turn fully."""
    from mechdyn.analyse.linkage_limits import branch_sweep
    return branch_sweep(linkage, linkage._last[linkage.independent[0]], points)


def plot_linkage(linkage, path=None, points=361, paths=None):
    """Four panels over a crank revolution: transmission functions (first order solid,
    second order dashed), ``I_red`` and ``dI_red/dphi``, the transmission angle of a
    four-bar (else the dependent positions), and the paths of ``paths`` (name ->
    point ``(x, y)`` expressions: coupler curves) with the joints' paths."""
    plt = pyplot()
    sweep = revolution(linkage, points)
    degrees = np.degrees(sweep.phi)
    crank = linkage.names[linkage.independent[0]]
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
    ax = axes[0, 0]
    for i in linkage.dependent:
        line, = ax.plot(degrees, sweep.ratio[i], label=f"d{sweep.names[i]}/d{crank}")
        ax.plot(degrees, sweep.second[i], ls="--", color=line.get_color(),
                label=f"d²{sweep.names[i]}/d{crank}²")
    ax.set_title("transmission functions")
    ax.legend(fontsize=7, ncol=2)
    ax = axes[0, 1]
    ax.plot(degrees, sweep.inertia, color="C0", label="I_red")
    ax.set_ylabel("I_red [kg m²]", color="C0")
    twin = ax.twinx()
    twin.plot(degrees, sweep.inertia_slope, color="C3", ls="--", label="dI_red/dphi")
    twin.set_ylabel(f"dI_red/d{crank} [kg m²/rad]", color="C3")
    ax.set_title("reduced inertia and its slope")
    _transmission_panel(linkage, sweep, axes[1, 0], degrees)
    _paths_panel(linkage, sweep, axes[1, 1], paths or {})
    for ax in (axes[0, 0], axes[0, 1], axes[1, 0]):
        ax.set_xlabel(f"crank angle {crank} [deg]")
        ax.grid(True, alpha=0.3)
    fig.suptitle(f"{linkage.mechanism.name} — kinematics over a crank revolution")
    return finish(fig, path)


def _transmission_panel(linkage, sweep, ax, degrees):
    try:
        angle = np.degrees(linkage.transmission_angle(sweep))
    except LinkageError:            # not a four-bar: the dependent positions instead
        units = linkage.mechanism.units
        lengths = [i for i in linkage.dependent if units.get(sweep.names[i], "rad") != "rad"]
        for i in linkage.dependent:
            if i not in lengths:
                ax.plot(degrees, np.degrees(sweep.q[i]), label=f"{sweep.names[i]} [deg]")
        ax.set_ylabel("angle [deg]")
        if lengths:
            twin = ax.twinx()
            for k, i in enumerate(lengths):
                unit = units[sweep.names[i]]
                twin.plot(degrees, sweep.q[i], ls="--", color=f"C{k + 5}",
                          label=f"{sweep.names[i]} [{unit}]")
            twin.set_ylabel("displacement (dashed)")
            twin.legend(fontsize=7, loc="lower right")
        ax.set_title("dependent coordinates")
        ax.legend(fontsize=7, loc="upper left")
        return
    ax.plot(degrees, angle, color="C2", label="transmission angle")
    ax.axhspan(40, 140, color="C2", alpha=0.08, label="40° .. 140°")
    worst = int(np.argmax(np.abs(angle - 90)))
    ax.plot(degrees[worst], angle[worst], "o", color="C3",
            label=f"worst {angle[worst]:.1f}° at {degrees[worst]:.1f}°")
    ax.set_ylim(0, 180)
    ax.set_ylabel("transmission angle [deg]")
    ax.set_title("transmission angle (coupler to rocker)")
    ax.legend(fontsize=8)


def _paths_panel(linkage, sweep, ax, paths):
    """Joint paths (grey), the linkage at the sweep's first position (bars between the
    joints of each link, dots at its points) and the paths of ``paths``."""
    joints = linkage.mechanism.joints
    start = {}
    for name, joint in joints.items():
        x, y = linkage.coupler_curve(joint.at, sweep)
        if np.ptp(x) + np.ptp(y) > 0:
            ax.plot(x, y, color="grey", lw=0.8)
        start[name] = (x[0], y[0])
        if joint.kind == "revolute":
            ax.annotate(name, start[name], fontsize=8, xytext=(3, 3),
                        textcoords="offset points")
    for k, (name, point) in enumerate(paths.items()):
        x, y = linkage.coupler_curve(point, sweep)
        ax.plot(x, y, color=f"C{k}", lw=1.6, label=f"path of {name}")
        ax.plot(x[0], y[0], "o", color=f"C{k}", ms=4)
    for link in linkage.mechanism.elements:
        corners = [start[n] for n, j in joints.items() if link in j.links and n in start]
        if len(corners) >= 2 and link != "frame":
            xs, ys = zip(*(corners + [corners[0]] if len(corners) > 2 else corners))
            ax.plot(xs, ys, color="k", lw=2.2, alpha=0.7)
    for x, y in start.values():
        ax.plot(x, y, "ko", ms=4)
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, alpha=0.3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("coupler curves and joint paths" if paths else "joint paths")
    if paths:
        ax.legend(fontsize=8)


def plot_kinetostatics(result, path=None):
    """Joint force magnitudes, the driving moment, and the shaking force and moment over
    the crank angle of a :class:`~mechdyn.analyse.joint_reactions.Kinetostatics`."""
    plt = pyplot()
    degrees = np.degrees(result.phi)
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 8.5))
    for name, reaction in result.reactions.items():
        if reaction.kind != "weld":          # a keyed flywheel: a moment, no force
            axes[0].plot(degrees, reaction.magnitude, label=f"{name} ({reaction.kind})")
    axes[0].set_ylabel("joint force |R| [N]")
    axes[0].set_title("joint reactions")
    axes[1].plot(degrees, result.driving, color="C3", label="driving moment")
    axes[1].axhline(np.mean(result.driving), color="C3", ls=":", label="mean")
    axes[1].set_ylabel("driving [N m]")
    axes[2].plot(degrees, result.shaking_force[0], label="shaking force x [N]")
    axes[2].plot(degrees, result.shaking_force[1], label="shaking force y [N]")
    axes[2].plot(degrees, result.shaking_moment, ls="--", label="shaking moment [N m]")
    axes[2].set_ylabel("on the frame")
    axes[-1].set_xlabel(f"crank angle {result.names[0]} [deg]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    omega = np.atleast_1d(result.omega)
    fig.suptitle(f"kinetostatics at omega = {omega[0]:.4g} rad/s")
    return finish(fig, path)


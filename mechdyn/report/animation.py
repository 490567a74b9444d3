"""Animations: the links drawn over a simulated motion, one frame per sample, as a GIF.

A link is drawn through its ``points`` (``mech.link(..., points=[(x1, y1), (x2, y2)])``:
joints, ends), or by default as its centre of mass with a tick along its ``angle``, so
a turning disc shows its turning. matplotlib draws the still parts once and the links
over them per frame (blitting); Pillow writes the frames as they come.

>>> import os, tempfile, mechdyn as md
>>> model = md.load_model("models/slider_crank.py")
>>> result = model.mechanism.simulate(model.scenes["startup"], model.params)
>>> gif = os.path.join(tempfile.mkdtemp(), "crank.gif")
>>> film = animate(model.mechanism, result, model.params, gif, sample=0.25)
>>> film.frames, film.times.tolist()
(5, [0.0, 0.25, 0.5, 0.75, 1.0])
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import sympy as sp

from mechdyn.errors import MechdynError
from mechdyn.symbols import t

__all__ = ["animate", "Film"]

_MAX_FRAMES = 5000


@dataclass(frozen=True)
class Film:
    """A written animation: the ``path``, the ``times`` of its frames, ``fps``.

    Examples
    --------
    >>> import numpy as np, mechdyn as md
    >>> from pathlib import Path
    >>> film = md.Film(Path("crank.gif"), np.array([0.0, 0.04, 0.08]), fps=25.0)
    >>> film.frames
    3
    """
    path: Path
    times: np.ndarray
    fps: float

    @property
    def frames(self) -> int:
        return len(self.times)


def animate(mechanism, result, params=None, path="animation.gif", sample=None, fps=25.0,
            size=5.0, dpi=80) -> Film:
    """Draw the links of ``mechanism`` over the motion of ``result`` into a GIF.

    Parameters
    ----------
    mechanism, result
        The mechanism and a result of simulating one of its scenes.
    params : dict
        Parameter values (the link geometry may use ones the scene does not).
    path : str
        The GIF to write.
    sample : float, optional
        Simulated time between frames; default ``1 / fps`` (real time).
    fps : float
        Frames per second of the film.
    size, dpi : float
        Width and height of the picture in inches, and its resolution.

    Returns
    -------
    Film

    Examples
    --------
    The shoe brake's disc, a frame every 25 s of its 50 s run:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> import os, tempfile
    >>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
    >>> gif = os.path.join(tempfile.mkdtemp(), "brake.gif")
    >>> film = md.animate(model.mechanism, res, model.params, gif, sample=25)
    >>> film.times.round(9).tolist(), os.path.getsize(gif) > 0
    ([0.0, 25.0, 50.0], True)
    """
    from PIL import Image

    from mechdyn.declare.parameters import ParameterSet
    from mechdyn.declare.scene import Scene
    from mechdyn.plotting import pyplot
    scene = result.scene if isinstance(result.scene, Scene) else None
    values = ParameterSet(params, mechanism=mechanism, scene=scene)
    if not fps > 0:
        raise MechdynError(f"animate: fps = {fps} must be positive")
    times = result.sample_times(sample if sample is not None else 1.0 / fps)
    if len(times) > _MAX_FRAMES:
        raise MechdynError(f"animate: {len(times)} frames; give a larger sample (at most "
                           f"{_MAX_FRAMES} frames)")
    drawn = _link_points(mechanism, result, values)
    states = result.trajectory.at(times)[:result.compiled.dof]
    paths = {name: f(times, states) for name, f in drawn.items()}   # (2, points, frames)
    _tick_scale(paths, drawn)
    plt = pyplot()
    figure, ax = plt.subplots(figsize=(size, size), dpi=dpi)
    everything = np.concatenate([p.reshape(2, -1) for p in paths.values()], axis=1)
    low, high = np.nanmin(everything, axis=1), np.nanmax(everything, axis=1)
    middle, half = (low + high) / 2, max(float(np.max(high - low)) / 2, 1e-9) * 1.15
    ax.set_xlim(middle[0] - half, middle[0] + half)
    ax.set_ylim(middle[1] - half, middle[1] + half)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, alpha=0.3)
    ax.set_title(f"{result.mechanism_name} — {result.scene.name}")
    lines = [ax.plot([], [], "o-", lw=3, ms=5, label=name, animated=True)[0]
             for name in paths]
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=9,
                    animated=True)
    ax.legend(handles=lines, loc="lower right", fontsize=7)
    figure.tight_layout()
    canvas = figure.canvas
    canvas.draw()
    background = canvas.copy_from_bbox(figure.bbox)

    def frames():
        for k in range(len(times)):
            canvas.restore_region(background)
            for line, xy in zip(lines, paths.values()):
                line.set_data(xy[0, :, k], xy[1, :, k])
                ax.draw_artist(line)
            clock.set_text(f"t = {times[k]:.3f} s")
            ax.draw_artist(clock)
            picture = Image.frombuffer("RGBA", canvas.get_width_height(),
                                       bytes(canvas.buffer_rgba()), "raw", "RGBA", 0, 1)
            yield picture.convert("RGB").convert("P", palette=Image.Palette.ADAPTIVE)
    sequence = frames()
    try:
        from mechdyn.atomic import replacing
        with replacing(path, "wb") as handle:
            next(sequence).save(handle, format="GIF", save_all=True, append_images=sequence,
                                loop=0, duration=1000.0 / fps, disposal=1)
    finally:
        plt.close(figure)
    return Film(Path(path), times, float(fps))


def _link_points(mechanism, result, values):
    """Per link, a function of (times, coordinate rows) -> array (2, points, frames);
    ``values``: a :class:`~mechdyn.declare.parameters.ParameterSet`."""
    from mechdyn.declare.elements import Link
    from mechdyn.declare.parameters import missing_values
    eqs = mechanism.equations(result.scene)
    drawn = {}
    for name, link in mechanism.elements.items():
        if not isinstance(link, Link):
            continue
        if link.points:
            points, tick = [(x, y) for x, y in link.points], False
        elif (link.x, link.y, link.angle) == (0, 0, 0):
            continue                                 # nothing moves: nothing to draw
        else:
            points, tick = [(link.x, link.y)], True
        exprs = [eqs.to_plain(sp.sympify(e)) for point in points for e in point]
        if tick:
            exprs += [eqs.to_plain(link.angle)]
        exprs = [sp.sympify(values.substitute(e)) for e in exprs]
        missing = set().union(*(e.free_symbols for e in exprs)) - set(eqs.q) - {t}
        if missing:
            raise missing_values(sorted(map(str, missing)), f"link {name!r} (animate)",
                                 mechanism.name)
        f = sp.lambdify((t, *eqs.q), exprs, "numpy")
        drawn[name] = _evaluator(f, len(points), tick)
    if not drawn:
        raise MechdynError(f"animate: {mechanism.name!r} has no link that moves")
    return drawn


def _evaluator(f, count, tick):
    def evaluate(times, states):
        rows = [np.broadcast_to(np.asarray(v, dtype=float), times.shape)
                for v in f(times, *states)]
        xy = np.array(rows[:2 * count]).reshape(count, 2, -1).transpose(1, 0, 2)
        if tick:          # centre and the direction of the angle, scaled later
            angle = rows[-1]
            xy = np.concatenate([xy, np.array([np.cos(angle), np.sin(angle)])[:, None]], 1)
        return xy
    evaluate.tick = tick
    return evaluate


def _tick_scale(paths, drawn):
    """Turn the default links' unit directions into ticks of a tenth of the picture."""
    points = [p[:, :-1] if drawn[n].tick else p for n, p in paths.items()]
    everything = np.concatenate([p.reshape(2, -1) for p in points], axis=1)
    extent = float(np.max(np.ptp(everything, axis=1)))
    length = 0.1 * extent if extent > 0 else 1.0
    for name, p in paths.items():
        if drawn[name].tick:
            p[:, -1] = p[:, 0] + length * p[:, -1]

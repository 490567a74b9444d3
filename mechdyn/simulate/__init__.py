"""Stage 4, simulate: the segment driver and its parts. Method choice, friction modes,
impacts, event location, closed-loop drift, compiled-kernel stepping, the segment
trajectory with dense output, and :class:`~mechdyn.simulate.result.Result`. Runs without
sympy. Imports earlier stages only.
"""

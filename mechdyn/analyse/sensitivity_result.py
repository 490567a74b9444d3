"""The result of :func:`mechdyn.analyse.sensitivities.sensitivities`: measures, their
derivatives with respect to parameters, units, and the relative sensitivities
``(dm/dp) (p/m)`` ("1 % more J_f changes fluctuation by -0.98 %").

>>> result = Sensitivities("disc", ("J",), {"J": 2.0}, ("t_end",), {"t_end": 4.0},
...                        [[2.0]], {"J": "kg*m^2", "t_end": "s"})
>>> result["t_end", "J"], result.relative("t_end", "J")
(2.0, 1.0)
>>> print(result)
disc: sensitivities (1 run)
measure  value  unit  parameter  derivative  unit        relative [%/%]
t_end        4  s     J                   2  s/(kg*m^2)               1
1 % more J changes t_end by 1 %
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mechdyn.errors import MechdynError
from mechdyn.tabular import Table

__all__ = ["Sensitivities", "derivative_unit"]


def derivative_unit(measure_unit: str, parameter_unit: str) -> str:
    """The unit of ``d measure / d parameter``."""
    def grouped(unit):
        return f"({unit})" if any(c in unit for c in "*/ ") else unit
    if parameter_unit in ("", "1"):
        return measure_unit or "1"
    return f"{measure_unit or '1'}/{grouped(parameter_unit)}"


@dataclass(frozen=True)
class Sensitivities:
    """Measures and their derivatives with respect to parameters.

    Attributes: ``name``, ``parameters`` (names), ``values`` (parameter name -> value),
    ``measures`` (names), ``results`` (measure -> value), ``gradients`` (one row per
    measure, one column per parameter), ``units`` (of measures and parameters, SI),
    ``runs`` (simulations or steady-running solves the derivatives took).
    ``result[measure, parameter]`` is one derivative.

    Examples
    --------
    >>> import mechdyn as md
    >>> brake = md.load_model("shoe_brake")
    >>> s = md.sensitivities(brake.mechanism, brake.scenes["braking"], brake.params,
    ...                      wrt=["I", "P"], measures=["t_end"])
    >>> s.parameters, s.measures, round(s["t_end", "P"], 9)
    (('I', 'P'), ('t_end',), -2.5)
    >>> s.units["t_end"], s.units["P"]
    ('s', 'N')
    """
    name: str
    parameters: tuple
    values: dict
    measures: tuple
    results: dict
    gradients: np.ndarray
    units: dict
    runs: int = 1

    def __post_init__(self):
        object.__setattr__(self, "gradients", np.asarray(self.gradients, dtype=float))

    def _index(self, measure, parameter) -> tuple:
        for item, known, what in ((measure, self.measures, "measure"),
                                  (parameter, self.parameters, "parameter")):
            if str(item) not in known:
                raise MechdynError(f"no {what} {item!r} here (these: {', '.join(known)})")
        return self.measures.index(str(measure)), self.parameters.index(str(parameter))

    def __getitem__(self, key) -> float:
        measure, parameter = key
        i, j = self._index(measure, parameter)
        return float(self.gradients[i, j])

    def gradient(self, measure) -> dict:
        """``{parameter: d measure / d parameter}``."""
        return {p: self[measure, p] for p in self.parameters}

    def relative(self, measure, parameter) -> float:
        """``(d m / d p) (p / m)``: the percent change of the measure per percent of the
        parameter (NaN where the measure is zero)."""
        value = self.results[str(measure)]
        scale = self.values[str(parameter)] / value if value != 0 else float("nan")
        return self[measure, parameter] * scale

    def table(self) -> Table:
        """One row per measure and parameter: value, derivative and relative change,
        with units."""
        rows = []
        for m in self.measures:
            for p in self.parameters:
                rows.append([m, self.results[m], self.units.get(m, ""), p, self[m, p],
                             derivative_unit(self.units.get(m, ""), self.units.get(p, "")),
                             self.relative(m, p)])
        return Table(["measure", "value", "unit", "parameter", "derivative", "unit",
                      "relative [%/%]"], rows, caption=f"{self.name}: sensitivities "
                     f"({self.runs} run{'s' * (self.runs != 1)})")

    def summary(self) -> str:
        """The table, and per measure the parameter it is most sensitive to."""
        lines = [self.table().text()]
        for m in self.measures:
            relative = {p: self.relative(m, p) for p in self.parameters}
            finite = {p: r for p, r in relative.items() if np.isfinite(r)}
            if finite:
                p = max(finite, key=lambda name: abs(finite[name]))
                lines.append(f"1 % more {p} changes {m} by {finite[p]:.3g} %")
        return "\n".join(lines)

    __str__ = summary

    def __repr__(self) -> str:
        return (f"<Sensitivities of {', '.join(self.measures)} to "
                f"{', '.join(self.parameters)} ({self.name})>")

    def _repr_html_(self) -> str:
        return self.table()._repr_html_()

    def plot(self, path=None):
        """A bar chart of the relative sensitivities, a group of bars per measure."""
        from mechdyn.plotting import finish, pyplot
        plt = pyplot()
        fig, ax = plt.subplots(figsize=(max(5.0, 1.2 * len(self.parameters) *
                                            len(self.measures)), 3.6))
        width = 0.8 / len(self.measures)
        x = np.arange(len(self.parameters))
        for i, m in enumerate(self.measures):
            ax.bar(x + (i - (len(self.measures) - 1) / 2) * width,
                   [self.relative(m, p) for p in self.parameters], width, label=m)
        ax.axhline(0, color="grey", lw=0.8)
        ax.set_xticks(x, self.parameters)
        ax.set_ylabel("% change per 1 % of the parameter")
        ax.set_title(f"{self.name}: relative sensitivities")
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(fontsize=8)
        return finish(fig, path)

"""What a result and a duty cycle's result share: dense states, columns sampled in time,
written to CSV (with display units) or handed to pandas.

>>> sample_times(0.0, 1.0, 0.25).tolist(), sample_times(0.0, 1.1, 0.5).tolist()
([0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.5, 1.0, 1.1])
"""
from __future__ import annotations

import csv

import numpy as np

from mechdyn.errors import MechdynError

__all__ = ["SeriesResult", "sample_times"]


class SeriesResult:
    """``final``, ``at``, ``sample_times``, ``to_csv`` and ``to_pandas`` of a result that
    has ``t``, ``state_names``, a ``trajectory``, ``res[key]``, ``_state_row(key)`` (the
    row of a coordinate or speed) and ``columns(sample)`` (time, text columns such as a
    duty cycle's ``phase``, and numbers)."""

    def final(self, key) -> float:
        """The last value of a coordinate, speed, acceleration or output."""
        return float(self[key][-1])

    def at(self, times, key=None):
        """Dense states at ``times``: a dict of all states, or one state's values."""
        states = self.trajectory.at(times)
        scalar = np.ndim(times) == 0
        if key is None:
            return {name: (row[0] if scalar else row)
                    for name, row in zip(self.state_names, states)}
        row = states[self._state_row(key)]
        return row[0] if scalar else row

    def sample_times(self, sample) -> np.ndarray:
        """``t_0, t_0 + sample, ...`` up to the end of the run (and the end itself)."""
        return sample_times(float(self.t[0]), float(self.t[-1]), sample)

    def to_csv(self, path, sample=None, units=None):
        """Write one column per series and a header row of names: the step points, or
        every ``sample`` seconds. ``units`` (``{"speed": "rpm"}``, see
        :class:`mechdyn.display.Display`) converts columns and names their units in
        the header (``phidot [rpm]``)."""
        data = self.columns(sample)
        if units is not None:
            from mechdyn.display import Display, column_units
            shown, si = Display(units), column_units(self)
            shown.check(si)
            converted = {}
            for name, values in data.items():
                if np.asarray(values).dtype == object:           # text: as it is
                    converted[name] = values
                    continue
                values, unit = shown.values(name, si.get(name, ""), values)
                converted[f"{name} [{unit}]" if unit else name] = values
            data = converted
        from mechdyn.atomic import replacing
        with replacing(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(list(data))
            for row in zip(*data.values()):
                writer.writerow([v if isinstance(v, str) else repr(float(v)) for v in row])
        return path

    def to_pandas(self):
        """The columns as a ``pandas.DataFrame`` (needs pandas)."""
        try:
            import pandas
        except ImportError:
            raise MechdynError("to_pandas() needs pandas: pip install pandas") from None
        return pandas.DataFrame(self.columns())


def sample_times(first, last, sample) -> np.ndarray:
    """``first, first + sample, ...`` up to ``last`` (and ``last`` itself)."""
    sample = float(sample)
    if not sample > 0 or not np.isfinite(sample):
        raise MechdynError(f"sample = {sample}: give a positive time step")
    count = int(np.floor((last - first) / sample * (1 + 1e-12))) + 1
    if count > 10_000_000:
        raise MechdynError(f"sample = {sample} s gives {count} rows over "
                           f"{last - first:.6g} s; choose a larger step")
    steps = np.arange(count)
    per_second = round(1 / sample)          # 0.001 s: t = k / 1000, exactly rounded
    times = first + (steps / per_second if per_second and
                     abs(1 / sample - per_second) <= 1e-9 * per_second else steps * sample)
    return times if last - times[-1] <= 1e-9 * max(sample, abs(last)) else \
        np.append(times, last)

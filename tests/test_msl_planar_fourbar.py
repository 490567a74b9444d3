"""The Modelica Standard Library's MultiBody.Loops.PlanarFourbar reference result,
reproduced through mechdyn's loop declaration (validation/msl/planar_fourbar)."""
from pathlib import Path

import numpy as np

import mechdyn as md

HERE = Path(__file__).resolve().parent.parent / "validation" / "msl" / "planar_fourbar"


def test_planar_fourbar_matches_the_msl_reference_within_its_tolerance():
    model = md.load_model(HERE / "model.py")
    reference = np.genfromtxt(HERE / "MultiBody.Loops.PlanarFourbar.csv", delimiter=",",
                              names=True)
    result = model.mechanism.simulate(model.scenes["msl"], model.params)   # defaults
    assert result.t_end == 5.0
    times = reference["time"]
    for column, key in (("revolute1phi", "phi_1"), ("revolute1w", "phidot_1")):
        expected = reference[column]
        span = expected.max() - expected.min()
        error = np.abs(result.at(times, key) - expected) / span
        assert error.max() < 2e-3, (column, error.max(), times[np.argmax(error)])

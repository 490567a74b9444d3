"""An element class defined outside mechdyn, in a module the tests' Dask workers can import
(``tests/`` is on their ``PYTHONPATH``, as a user's own module would be installed on a
cluster's workers): the preloaded torsional spring of the README."""
from dataclasses import dataclass

import mechdyn as md


@dataclass(frozen=True)
class PreloadedSpring(md.Element):
    """Relaxed at q0, preloaded with M0: the moment -(k (along - q0) + M0) on along."""
    k: object = 0
    q0: object = 0
    M0: object = 0
    along: object = None
    DEPENDS = {"k": "", "q0": "", "M0": ""}
    MOVING = ("along",)

    def __post_init__(self):
        super().__post_init__()
        for attribute in ("k", "q0", "M0", "along"):
            self.convert(attribute)

    def expressions(self):
        return {"k": self.k, "q0": self.q0, "M0": self.M0, "along": self.along}

    def work(self, motion):
        angle = motion.position(self.along, self.name)
        k, q0, M0 = (motion.plain(value) for value in (self.k, self.q0, self.M0))
        return md.Work(potential=k * (angle - q0) ** 2 / 2 + M0 * angle,
                       forces=((-(k * (angle - q0) + M0), angle),))

    def check_units(self, units):
        units.same("q0", "along")
        units.work("M0 * d(along)/d{q}", "along", "M0")
        units.work("k * along * d(along)/d{q}", "along", "k", "along")

"""The user's :class:`Mechanism`: the declared mechanism of :mod:`mechdyn.declare` with
the later stages at hand (derive, print, compile, simulate, linearise, show). It sits
above every stage, as the command line does; ``md.Mechanism`` is this class.

>>> import sympy as sp, mechdyn as md
>>> phi = md.coordinate("phi")
>>> J1, m3, l = sp.symbols("J_1 m_3 l", positive=True)
>>> yoke = md.Mechanism("Scotch yoke", coordinates=[phi])
>>> _ = yoke.link("crank", J=J1, angle=phi)
>>> _ = yoke.link("yoke", m=m3, x=l * sp.cos(phi))
>>> yoke.reduced_inertia()
J_1 + l**2*m_3*sin(phi)**2
"""
from __future__ import annotations

from mechdyn.declare import mechanism as declared
from mechdyn.derive import equations as derived

__all__ = ["Mechanism"]


class Mechanism(declared.Mechanism):
    __doc__ = declared.Mechanism.__doc__

    def equations(self, scene=None):
        """Lagrange's equations ``M(q) q'' = f(q, q', t)`` (an :class:`Equations`),
        for all elements or for those a :class:`Scene` calls for."""
        return derived.equations(self, scene)

    def check_dimensions(self, scene=None):
        """Check the dimension of every element's contribution to every equation (and,
        with a scene, its stop conditions and initial values); raises a
        :class:`DeclarationError` naming the element and both dimensions. Runs by
        itself when equations are derived, if parameter units are declared."""
        derived.check_dimensions(self, scene)

    def reduced_inertia(self, scene=None):
        """The reduced (equivalent) moment of inertia of a one-DOF mechanism; with
        closed loops an expression of the crank angle and the dependent coordinates."""
        return derived.reduced_inertia(self, scene)

    def reduced_moment(self, scene=None):
        """The reduced moment of a one-DOF mechanism (includes gravity and springs)."""
        return derived.reduced_moment(self, scene)

    def transmission_functions(self, order=1, scene=None) -> dict:
        """Of a one-DOF linkage: ``dq/dphi`` (``order=1``) or ``d2q/dphi2`` (2, written
        in the first-order ones, ``theta_2'``) of each dependent coordinate, by its
        plain symbol; expressions of the crank angle and the dependent coordinates."""
        return derived.transmission_functions(self, order, scene)

    def latex(self, scene=None, expanded=False) -> str:
        """The derivation as LaTeX: positions, transmission functions and element laws
        as named quantities, energies, reduced quantities, equations (``expanded``:
        every term written out in the coordinates)."""
        from mechdyn.derive.latex import derivation_latex
        return derivation_latex(derived.printed_equations(self, scene), expanded)

    def derivation(self, scene=None):
        """The derivation as a textbook writes it, as data (a
        :class:`~mechdyn.derive.textbook.Derivation`): ``quantities`` (named symbol ->
        definition), ``reduced_inertia``, ``reduced_inertia_slope``, ``reduced_moment``,
        ``mass_matrix``, ``forces`` in the named quantities; ``expand(expr)``."""
        from mechdyn.derive.textbook import textbook
        return textbook(derived.printed_equations(self, scene))

    def compile(self, scene):
        """The scene's compiled functions (``rhs``, ``jac`` in solve_ivp's ``(t, y)``
        form after binding ``p``), cached: a :class:`~mechdyn.compile.compiler.CompiledScene`."""
        from mechdyn.compile.compiler import compile_scene
        return compile_scene(self, scene)

    def simulate(self, scene, params=None, **options):
        """Integrate a :class:`Scene`; returns a :class:`Result` (its ``units``: the SI
        unit of each coordinate and output). ``options``: ``progress``, ``max_steps``,
        ``max_wall_time``, ``backend``, ``start`` of
        :func:`mechdyn.simulate.simulation.simulate`."""
        from mechdyn.simulate.simulation import simulate
        return simulate(self, scene, params or {}, **options)

    def sensitivities(self, scene, params, wrt, measures=("t_end",), **options):
        """Exact derivatives of ``measures`` with respect to the parameters ``wrt`` from
        the forward sensitivity equations (a :class:`~mechdyn.Sensitivities`);
        ``options``: ``cycle``, ``speed_guess`` of
        :func:`mechdyn.analyse.sensitivities.sensitivities`."""
        from mechdyn.analyse.sensitivities import sensitivities
        return sensitivities(self, scene, params or {}, wrt, measures, **options)

    def linearize(self, scene=None, at=None, params=None, inputs=(), outputs=()):
        """State-space matrices A, B, C, D about an operating point ``at`` (a
        :class:`~mechdyn.derive.linear.StateSpace`; inputs: parameters, outputs:
        coordinates, speeds, element names or expressions)."""
        from mechdyn.derive.linear import linearize
        return linearize(self, scene, at, params, inputs, outputs)

    def export_fmu(self, scene, params, path, inputs=(), start=None):
        """Write ``scene`` as an FMI 2.0 Model Exchange FMU ``path`` (``.fmu``): C built
        with the system compiler, parameters ``params`` as start values; ``inputs``:
        parameters (or loads of one parameter) the FMU reads from outside; ``start``: a
        state ``[q..., u...]`` replacing the scene's initial values
        (:func:`mechdyn.report.fmu.export_fmu`)."""
        from mechdyn.report.fmu import export_fmu
        return export_fmu(self, scene, params or {}, path, inputs, start)

    def _repr_latex_(self):
        return self.equations()._repr_latex_()

    def _repr_html_(self):
        """Jupyter: the elements as a table and the derivation."""
        from mechdyn.report.document import mechanism_html
        return mechanism_html(self)

"""Generated functions of a linkage's analysis: the loops' residuals and Jacobian, the
bias of their second derivative, the mass matrix, the velocity terms of the forcing and
the generalized forces element by element, all of ``(t, [q, u], p)`` (see
:mod:`mechdyn.compile.codegen`).
"""
from __future__ import annotations

import numpy as np
import sympy as sp

from mechdyn.compile.codegen import list_function, safe_symbols
from mechdyn.errors import ParameterError
from mechdyn.symbols import t

__all__ = ["LinkageFunctions"]


class LinkageFunctions:
    """The loops' closure and bias, the mass matrix, the velocity terms and the
    generalized forces (per element) as generated code of ``(t, [q, u], p)``."""

    def __init__(self, eqs):
        n = eqs.dof
        self.eqs = eqs
        self.force_names = [name for name in eqs.generalized_forces
                            if name not in {fr.name for fr in eqs.frictions}]
        columns = [eqs.generalized_forces[name] for name in self.force_names]
        everything = [eqs.mass_matrix, eqs.inertial_forcing, *columns] + \
            [c.expression for c in eqs.constraints] + [c.bias for c in eqs.constraints]
        known = set(eqs.q) | set(eqs.u) | {t}
        self.params = sorted(set().union(*(sp.sympify(e).free_symbols for e in everything))
                             - known, key=lambda s: s.name)
        q_names, u_names = safe_symbols("q", n), safe_symbols("u", n)
        p_names = safe_symbols("p", len(self.params))
        self.rename = dict(zip(eqs.q, q_names)) | dict(zip(eqs.u, u_names)) | \
            dict(zip(self.params, p_names))
        self.arguments = [str(s) for s in q_names + u_names]
        self.parameters = [str(s) for s in p_names]
        grads = [g for c in eqs.constraints for g in c.gradient]
        self.closure = self._function("closure", [c.expression for c in eqs.constraints]
                                      + grads)
        self.bias = self._function("bias", [c.bias for c in eqs.constraints])
        self.mass = self._function("mass", list(eqs.mass_matrix))
        self.inertial = self._function("inertial", list(eqs.inertial_forcing))
        flat = self._function("forces", [e for column in columns for e in column])
        self.forces = lambda t_value, y, p: np.array(flat(t_value, y, p)).reshape(len(columns), n)

    def _function(self, name, exprs):
        exprs = [sp.sympify(e).xreplace(self.rename) for e in exprs]
        return list_function(name, self.arguments, self.parameters, exprs)

    def expressions(self, exprs):
        """A generated function of user expressions (coordinates as functions of t)."""
        plain = [self.eqs.to_plain(sp.sympify(e)) for e in exprs]
        extra = set().union(*(e.free_symbols for e in plain)) - set(self.rename) - {t}
        if extra:
            raise ParameterError(f"expressions use {sorted(map(str, extra))}, which the "
                                 "linkage has no values for")
        return self._function("evaluated", plain)

    def parameter_vector(self, params) -> list:
        """``p`` from parameter values (a checked
        :class:`~mechdyn.declare.parameters.ParameterSet`, or a dict by symbol or name)."""
        from mechdyn.declare.parameters import ParameterSet
        values = params if isinstance(params, ParameterSet) else ParameterSet(params)
        return values.vector([s.name for s in self.params], "the linkage analysis")

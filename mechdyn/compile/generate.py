"""Generation: a scene's equations -> the source of its numeric functions.

Every function has the signature ``f(t, y, p, out)`` (see :mod:`mechdyn.compile.codegen`). The
state is ``y = [q_1..q_n, u_1..u_n]``; the parameter vector ``p`` holds the scene's
parameters sorted by name, then one sign per friction element (+1 or -1: sliding that
way and pushing against it; 0: no sliding force, the element is stuck and acts as a
constraint). The functions:

- ``rhs``: ``dy/dt = [u, M^-1 f]`` with sliding frictions pushing ``-sign * magnitude``;
  ``M a = f`` solved by an unrolled Cholesky factorisation (NaN where ``M`` is not
  positive definite, so a solver rejects the step);
- ``jac``: its analytic Jacobian, ``out`` a ``2n x 2n`` array;
- ``terms``: the pieces the friction modes need, laid out as ``meta["terms"]`` says
  (name, offset, shape): the lower triangle of ``M``, ``f``, per friction element
  (``meta["friction_kinds"]``: "friction", "one_way", "gear") its gradient, the velocity
  part of its second derivative (``bias``), its magnitude, sliding rate, ``peak`` and
  ``release``; per stop limit (``meta["contacts"]``) its gradient, bias, rate, gap and
  restitution; per lossy gear (``meta["gears"]``: name, its friction element, its
  constraint) its law ``(eta_forward, eta_backward, bearing_forward, bearing_backward)``;
  the closed loops' gradients, biases and rates;
- ``events``: the stop conditions, the friction elements' sliding rates and magnitudes,
  the stop limits' gaps (kind "gap": watched falling through zero while the limit is
  open; right after an impact the gap may be a rounding below zero, so the watch starts
  from min(gap, 0) at the segment's start), and the switching functions (where a
  ``Piecewise``, ``Min``, ``Max``, ``Abs``, ``sign`` or ``Heaviside`` of the forcing
  changes branch), in the order of ``meta["events"]``; the branches are locked by flags
  in ``p`` after the friction signs (:class:`Switches`); last, the domain conditions
  (:func:`domain_conditions`: an argument that must not be negative for an element's
  expression to have a real value), and the mass matrix's margin from singular
  (kind "mass": :func:`~mechdyn.compile.mass_solve.mass_margin_event`);
- ``outputs`` (:mod:`mechdyn.compile.output_code`), ``energy`` (``[T, V]``);
- ``mass_factor`` (a mass matrix of the parameters alone, ``meta["mass_factor"]``:
  offset in ``p`` and size): its factor, appended to ``p`` once per parameter vector
  (:meth:`~mechdyn.compile.generated.CompiledScene.mass_factor`) and read by ``rhs``
  and ``jac``.

A magnitude written with ``|rate|`` of its own sliding rate (Stribeck, tables) is
compiled with ``sign * rate``: no switching function at zero sliding speed.
"""
from __future__ import annotations

import sympy as sp
from mechdyn.compile.codegen import function_source, safe_symbols
from mechdyn.compile.table_code import table_constants
from mechdyn.compile.output_code import friction_signed, outputs as scene_outputs, slip_signed
from mechdyn.symbols import t, written
from mechdyn.compile.mass_solve import (UNROLLED_LIMIT, _jac_source, _rhs_source, factor_source,
                                        is_constant, jacobian_pattern, mass_margin_event)

__all__ = ["generate"]


def generate(eqs, selected) -> tuple:
    """Metadata and generated source for the equations ``eqs`` of a scene's selection
    ``selected`` (a :class:`~mechdyn.derive.selection.Selection`: its elements, loops,
    outputs and stop conditions)."""
    n, frictions = eqs.dof, eqs.frictions
    state = set(eqs.q) | set(eqs.u) | {t}
    outputs = scene_outputs(eqs, selected)
    stops = [(repr(c), eqs.to_plain(c.expression - c.value)) for c in selected.until]
    signs = safe_symbols("s", len(frictions))
    switches = Switches(set(eqs.q) | set(eqs.u) | {t})
    magnitudes = [switches.lock(slip_signed(fr, sign)) for fr, sign in zip(frictions, signs)]
    contacts, gears = eqs.contacts, eqs.gears
    locked = {name: [switches.lock(e) for e in exprs] for name, exprs in (
        ("peak", [fr.peak for fr in frictions]), ("release", [fr.release for fr in frictions]),
        ("gap", [c.gap for c in contacts]), ("restitution", [c.restitution for c in contacts]),
        ("law", [e for g in gears for e in g.law]))}
    mass_matrix = switches.lock(eqs.mass_matrix)
    forcing = switches.lock(eqs.smooth_forcing)
    for sign, fr, magnitude in zip(signs, frictions, magnitudes):
        # a magnitude below zero pushes nothing: max(m, 0) is continuous, not a switch
        forcing = forcing - sign * sp.Max(magnitude, 0) * fr.gradient
    output_exprs = [switches.lock(friction_signed(e, eqs, signs)) for _, e, _ in outputs]
    flags = switches.flags
    # the events' own sines and cosines of t bound the step too (a fast oscillating
    # condition on a slow state is sampled at least 16 times a period)
    periods = _forcing_periods([forcing] + magnitudes + [e for _, e in stops]
                               + switches.functions, set(eqs.q) | set(eqs.u))
    everything = [mass_matrix, forcing, eqs.kinetic_energy, eqs.potential_energy]
    everything += magnitudes + [e for _, e in stops] + output_exprs
    everything += [e for exprs in locked.values() for e in exprs]
    everything += [c.expression for c in eqs.constraints]       # a loop's ground length
    known = set(eqs.q) | set(eqs.u) | {t} | set(signs) | set(flags)
    params = sorted(set().union(*(sp.sympify(e).free_symbols for e in everything)) - known,
                    key=lambda s: s.name)
    q_names, u_names = safe_symbols("q", n), safe_symbols("u", n)
    rename = dict(zip(eqs.q, q_names)) | dict(zip(eqs.u, u_names))
    rename |= dict(zip(params, safe_symbols("p", len(params))))
    rename[t] = sp.Symbol("t", real=True)

    def r(expr):
        return sp.sympify(expr).xreplace(rename)

    coordinates = [str(q) for q in eqs.q]
    state_names = coordinates + [str(u) for u in eqs.u]
    states = [str(s) for s in q_names + u_names]
    parameters = [f"p{i}" for i in range(len(params))] + [str(s) for s in signs + flags]
    doc = (f"y = [{', '.join(state_names)}]; p = [" + ", ".join(
        [s.name for s in params] + [f"sign of {fr.name}" for fr in frictions]
        + [f"side of {f}" for f in switches.functions]) + "]")

    def source(name, exprs, body, lines=()):
        return function_source(name, states, parameters, exprs, body, doc, lines,
                               large=n > UNROLLED_LIMIT)

    mass, force = r(mass_matrix), r(forcing)
    constraints = eqs.constraints
    layout, term_exprs = _terms_layout(n, mass, force, [
        ("friction_gradient", (len(frictions), n), [r(g) for fr in frictions for g in fr.gradient]),
        ("friction_bias", (len(frictions),), [r(fr.bias) for fr in frictions]),
        ("friction_magnitude", (len(frictions),), [r(m) for m in magnitudes]),
        ("friction_rate", (len(frictions),), [r(fr.rate) for fr in frictions]),
        ("constraint_gradient", (len(constraints), n),
         [r(g) for c in constraints for g in c.gradient]),
        ("constraint_bias", (len(constraints),), [r(c.bias) for c in constraints]),
        ("constraint_rate", (len(constraints),),
         [r(sp.diff(c.expression, t)) for c in constraints]),
        ("friction_peak", (len(frictions),), [r(e) for e in locked["peak"]]),
        ("friction_release", (len(frictions),), [r(e) for e in locked["release"]]),
        ("contact_gradient", (len(contacts), n), [r(g) for c in contacts for g in c.gradient]),
        ("contact_bias", (len(contacts),), [r(c.bias) for c in contacts]),
        ("contact_rate", (len(contacts),), [r(c.rate) for c in contacts]),
        ("contact_gap", (len(contacts),), [r(e) for e in locked["gap"]]),
        ("contact_restitution", (len(contacts),), [r(e) for e in locked["restitution"]]),
        ("gear_law", (len(gears), 4), [r(e) for e in locked["law"]])])
    domains = domain_conditions(eqs, selected.elements, state) + [
        (f"output {label!r} = {written(expr)}", g)
        for (label, expr, _), plain in zip(outputs, output_exprs)
        for g in _domain_arguments(plain) if g.free_symbols & state and not g.is_nonnegative]
    # an expression without effect (the angle of a link without inertia) is not watched
    # where it names a parameter nothing else needs: p holds only the needed ones
    domains = [(label, g) for label, g in domains if g.free_symbols - known <= set(params)]
    event_exprs = [r(e) for _, e in stops] + [r(fr.rate) for fr in frictions] \
        + [r(m) for m in magnitudes] + [r(e) for e in locked["gap"]] \
        + [r(e) for e in switches.functions] + [r(e) for _, e in domains]
    margin = None if eqs.constraints else mass_margin_event(mass_matrix, state)
    event_exprs += [] if margin is None else [r(margin)]
    first_switch = len(stops) + 2 * len(frictions) + len(contacts)
    candidates = [*range(len(stops)), *range(first_switch,
                                              first_switch + len(switches.functions))]
    timed = [i for i in candidates if _of_time_alone(event_exprs[i])]   # stops, switches
    factor_at, pattern = None, None
    if constraints:      # closed loops: rhs solves M a = f + G' lambda, G a = -bias
        from mechdyn.compile.loop_code import loop_sources
        loops = loop_sources(eqs, mass, force, rename, source, states)
        sources = [loops.pop("rhs"), loops.pop("jac"), *loops.values()]
    else:    # a constant M: factored once per parameter vector, appended to p
        factor_at = len(parameters) if is_constant(mass) else None
        sources = [_rhs_source(source, mass, force, n, states, coordinates, factor_at),
                   _jac_source(source, mass, force, q_names, u_names, factor_at)]
        pattern = jacobian_pattern(mass, force, q_names, u_names)
        if factor_at is not None:
            factor, size = factor_source(source, mass)
            sources.append(factor)
            mass_factor = [factor_at, size]
    sources += [
        _terms_source(source, term_exprs),
        source("events", event_exprs, [f"out[{i}] = {{{i}}}" for i in range(len(event_exprs))]),
        source("outputs", [r(e) for e in output_exprs],
               [f"out[{i}] = {{{i}}}" for i in range(len(output_exprs))]),
        source("energy", [r(eqs.kinetic_energy), r(eqs.potential_energy)],
               ["out[0] = {0}", "out[1] = {1}"]),
        source("periods", [r(e) for e in periods],
               [f"out[{i}] = {{{i}}}" for i in range(len(periods))]),
        source("timed", [event_exprs[i] for i in timed],
               [f"out[{k}] = {{{k}}}" for k in range(len(timed))]),
    ]
    meta = {
        "coordinates": coordinates,
        "state_names": state_names,
        "acceleration_names": [str(a) for a in eqs.a],
        "param_names": [s.name for s in params],
        "frictions": [fr.name for fr in frictions],
        "frozen": [_frozen_index(fr, state) for fr in frictions],
        "friction_kinds": [fr.kind for fr in frictions],
        "contacts": [c.name for c in contacts],
        "contact_elements": [c.element for c in contacts],
        "contact_frozen": [_frozen_index(c, state) for c in contacts],
        "gears": [[g.name, g.friction, g.constraint] for g in gears],
        "stop_labels": [label for label, _ in stops],
        "output_labels": [label for label, _, _ in outputs],
        "output_items": [item for _, _, item in outputs],
        "terms": layout,
        "events": [["stop", label] for label, _ in stops]
        + [["rate", fr.name] for fr in frictions]
        + [["magnitude", fr.name] for fr in frictions]
        + [["gap", c.name] for c in contacts]
        + [["switch", str(e)] for e in switches.functions]
        + [["domain", label] for label, _ in domains]
        + ([] if margin is None else [["mass", "mass matrix"]]),
        "periods": len(periods),
        "timed": timed,
        "revolving": _revolving([mass_matrix, forcing] + magnitudes + [
            e for exprs in locked.values() for e in exprs] + [
            c.expression for c in eqs.constraints], eqs.q),
        "autonomous": not any(t in sp.sympify(e).free_symbols
                              for e in [mass_matrix, forcing] + magnitudes),
        "eliminated": {c.func.__name__: str(e) for c, e in eqs.eliminated.items()},
        "elements": list(eqs.elements), "excluded": list(eqs.excluded),
        "rigid": list(eqs.rigid),
        "time_functions": [c.func.__name__ for c in eqs.coordinates],
    }
    if pattern is not None:
        meta["jac_sparsity"] = pattern           # [rows, columns] of the non-zero entries
    if factor_at is not None:
        meta["mass_factor"] = mass_factor        # [offset in p, entries]
    if constraints:
        meta["constraints"] = [c.name for c in constraints]
        meta["loops"] = [next(name for name, labels in selected.loops.items()
                              if c.name in labels) for c in constraints]
        meta["independent"] = [eqs.q.index(q) for q in eqs.independent]
        meta["multiplier_outputs"] = {label: meta["constraints"].index(label)
                                      for label, _, _ in outputs
                                      if label in meta["constraints"]}
    return meta, table_constants(everything) + "\n".join(sources)


# ------------------------------------------------------------------ switching points
class Switches:
    """The switching functions of a set of expressions and their locked forms.

    Each ``Piecewise`` condition, ``Min``/``Max``, ``Abs``, ``sign`` and ``Heaviside`` of
    the state or time is rewritten to take its branch from a *flag* (a run-time
    parameter, +1 or -1: the side of the switching function at the start of the
    segment); a flag of 0 unlocks it (the branch is decided by the state itself). Within
    a segment the equations are then smooth, the solver never steps into a jump, and the
    crossing of the switching function is an event after which the next segment takes
    the other branch (Modelica's discontinuity locking). Functions of the parameters
    alone are left as they are.

    ``functions``: the switching functions; ``flags``: their flag symbols;
    ``lock(expr)``: the expression with its switches locked.
    """

    def __init__(self, variables):
        self.variables = variables
        self.functions, self.flags = [], []

    def lock(self, expr):
        expr = sp.sympify(expr)
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(lambda e: self.lock(e) if e != 0 else e)
        return expr.replace(lambda e: isinstance(e, (sp.Min, sp.Max, sp.Abs, sp.sign,
                                                     sp.Heaviside, sp.Piecewise)),
                            self._locked)

    def _locked(self, e):
        if isinstance(e, sp.Piecewise):
            return sp.Piecewise(*[(value, self._condition(c)) for value, c in e.args],
                                evaluate=False)
        if isinstance(e, (sp.Min, sp.Max)):
            *rest, last = e.args
            chosen = last
            pick = sp.Gt if isinstance(e, sp.Max) else sp.Lt
            for arg in reversed(rest):
                chosen = sp.Piecewise((arg, self._condition(pick(arg, chosen))), (chosen, True))
            return chosen
        x = e.args[0]
        if isinstance(e, sp.Abs):
            return sp.Piecewise((x, self._condition(sp.Ge(x, 0))), (-x, True))
        if isinstance(e, sp.sign):
            return sp.Piecewise((1, self._condition(sp.Gt(x, 0))),
                                (-1, self._condition(sp.Lt(x, 0))), (0, True))
        return sp.Piecewise((1, self._condition(sp.Gt(x, 0))), (0, True))   # Heaviside

    def _condition(self, condition):
        if isinstance(condition, (sp.And, sp.Or, sp.Not)):
            return condition.func(*[self._condition(a) for a in condition.args])
        if not isinstance(condition, sp.core.relational.Relational) or \
                isinstance(condition, (sp.Eq, sp.Ne)):
            return condition
        g = sp.expand(condition.lhs - condition.rhs)
        if not (g.free_symbols & self.variables):
            return condition
        flag, orientation = self._flag(g)
        side = flag * orientation
        positive = isinstance(condition, (sp.Gt, sp.Ge))
        locked = sp.Gt(side, 0) if positive else sp.Lt(side, 0)
        return sp.Or(sp.And(sp.Eq(flag, 0), condition), sp.And(sp.Ne(flag, 0), locked))

    def _flag(self, g):
        """The flag of the (expanded) switching function ``g`` or of ``-g``, found by
        their canonical forms (one lookup each, whatever the number of switches)."""
        known = self.__dict__.setdefault("_known", {})
        for key, orientation in ((g, 1), (sp.expand(-g), -1)):
            if key in known:
                return self.flags[known[key]], orientation
        known[g] = len(self.functions)
        self.functions.append(g)
        self.flags.append(sp.Symbol(f"w{len(self.flags)}", real=True))
        return self.flags[-1], 1


def domain_conditions(eqs, elements, variables) -> list:
    """``(label, g)`` for every argument ``g`` of the scene's element expressions that
    must not become negative for the expression to have a real value (a square root
    or fractional power, a logarithm, an arcsine or arccosine: ``1 - x^2``), where it
    depends on the state or time. A run stops where one does, naming the element."""
    found = []
    for name, element in elements.items():
        if name not in eqs.elements and type(element).__name__ != "Link":
            continue
        kind = type(element).__name__.lower()
        for attribute, expr in element.expressions().items():
            plain = eqs.to_plain(sp.sympify(expr))
            for g in _domain_arguments(plain):
                if g.free_symbols & variables and not g.is_nonnegative:
                    found.append((f"{kind} {name!r}: {attribute} = {written(expr)}", g))
    return found


def _domain_arguments(expr) -> list:
    out = []
    for node in sp.preorder_traversal(expr):
        if isinstance(node, sp.Pow) and not node.exp.is_integer:
            out.append(node.base)
        elif isinstance(node, sp.log):
            out.append(node.args[0])
        elif isinstance(node, (sp.asin, sp.acos)):
            out.append(1 - node.args[0] ** 2)
    return out


def _forcing_periods(expressions, states) -> list:
    """Periods ``2 pi / |omega|`` of the sines and cosines of ``omega t + c`` in the
    forcing (``omega`` free of the state and of t): a step must not skip over them while
    nothing else changes."""
    periods = []
    for expr in expressions:
        for entry in (sp.Matrix(expr) if isinstance(expr, sp.MatrixBase) else [expr]):
            for node in sp.preorder_traversal(sp.sympify(entry)):
                if isinstance(node, (sp.sin, sp.cos)) and node.args[0].has(t):
                    omega = sp.diff(node.args[0], t)
                    if omega != 0 and not (omega.free_symbols & ({t} | states)):
                        period = 2 * sp.pi / sp.Abs(omega)
                        if period not in periods:
                            periods.append(period)
    return periods


def _revolving(expressions, coordinates) -> list:
    """The indices of the coordinates the equations repeat in after a turn of 2 pi
    (they enter only through sines and cosines): their size means nothing, and the
    error control weighs them on the scale of one revolution. Each coordinate is turned
    in the entries that hold it only (a chain's coordinate is in a few of its n^2)."""
    holding = {q: [] for q in coordinates}
    for expression in expressions:
        expression = sp.sympify(expression)
        entries = expression.values() if isinstance(expression, sp.MatrixBase) \
            else [expression]
        for entry in entries:
            for q in entry.free_symbols & holding.keys():
                holding[q].append(entry)
    return [i for i, q in enumerate(coordinates) if holding[q]
            and all(e.xreplace({q: q + 2 * sp.pi}) == e for e in holding[q])]


def _of_time_alone(expr) -> bool:
    """Whether an event function (renamed: states ``q*``/``u*``, parameters ``p*``,
    signs ``s*``, flags ``w*``) depends on t and on parameters only: its crossings are
    known without the state (:mod:`mechdyn.simulate.time_events`)."""
    names = {s.name for s in sp.sympify(expr).free_symbols}
    return "t" in names and all(n == "t" or (n[0] == "p" and n[1:].isdigit())
                                for n in names)


# ------------------------------------------------------------------------- helpers
def _terms_layout(n, mass, forcing, groups):
    """The ``terms`` vector: lower triangle of ``M``, ``f``, then ``groups`` of
    ``(name, shape, expressions)``; returns the layout and the expressions."""
    layout, exprs = [], []

    def add(name, shape, entries):
        layout.append([name, len(exprs), list(shape)])
        exprs.extend(entries)
    add("mass", (n * (n + 1) // 2,), [mass[i, j] for i in range(n) for j in range(i + 1)])
    add("forcing", (n,), list(forcing))
    for name, shape, entries in groups:
        add(name, shape, entries)
    return layout, exprs


def _terms_source(source, exprs):
    """``terms`` writing only its non-zero entries (the caller's ``out`` is zeros): a
    large model's mass matrix is mostly zeros."""
    nonzero = [i for i, e in enumerate(exprs) if e != 0]
    return source("terms", [exprs[i] for i in nonzero],
                  [f"out[{i}] = {{{k}}}" for k, i in enumerate(nonzero)])


def _frozen_index(friction, state) -> int:
    """The coordinate a stuck friction (or a stop in contact) fixes, when its gradient
    is one entry free of the state (``state``: coordinates, speeds, time) that is a
    number or non-zero by its parameters' assumptions (a gear ratio ``i``, positive)."""
    nonzero = [i for i, g in enumerate(friction.gradient) if g != 0]
    if len(nonzero) != 1:
        return -1
    entry = friction.gradient[nonzero[0]]
    if not entry.free_symbols & state and (entry.is_number or entry.is_nonzero):
        return nonzero[0]
    return -1

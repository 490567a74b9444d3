"""Compilation: a scene's equations -> fast scalar Python functions, cached.

The state vector is ``y = [q_1..q_n, u_1..u_n]`` (coordinates, then speeds); the parameter
vector ``p`` holds the scene's parameters sorted by name, then one sign per friction
element (+1, -1 sliding that way, 0 stuck). Every generated function has the signature
``f(t, y, p)`` and a docstring stating these orders. ``M(q) a = f`` is solved numerically
(unrolled Cholesky in the generated code), never symbolically.

A compiled scene is cached in memory and on disk (``$MECHDYN_CACHE``, default
``~/.cache/mechdyn``; ``MECHDYN_CACHE=off`` disables the disk), keyed by a hash of the
mechanism's declaration and the scene's effects, rigid springs, stop conditions and
outputs: a second run of the same model skips derivation and compilation.

>>> import mechdyn as md
>>> phi = md.coordinate("phi")
>>> disc = md.Mechanism("disc", [phi])
>>> _ = disc.link("disc", J=2, angle=phi)
>>> _ = disc.load("drive", 6, along=phi)
>>> scene = md.Scene("spin", initial={phi: 0, md.speed(phi): 0}, t_end=1)
>>> compiled = compile_scene(disc, scene)
>>> compiled.rhs(0.0, [0.0, 1.0], compiled.parameter_vector({}))
[1.0, 3.0]
"""
from __future__ import annotations

import hashlib
import json
import math
import os
from pathlib import Path

import numpy as np
import sympy as sp

from . import __version__
from .codegen import compile_source, function_source, safe_symbols
from .elements import Constraint, Damper, Friction, Load, Spring
from .errors import ParameterError, SceneError, SimulationError
from .scene import selection
from .symbols import t

__all__ = ["CompiledScene", "compile_scene", "SingularMassError"]

_UNROLLED_LIMIT = 8          # DOF up to which the Cholesky solve is unrolled in code
_memory_cache: dict = {}


class SingularMassError(SimulationError):
    """The mass matrix (reduced inertia) is not positive definite at a state."""

    def __init__(self, coordinate, t_value, state):
        self.coordinate, self.time, self.state = coordinate, t_value, list(state)
        super().__init__(f"the mass matrix is singular or not positive definite in "
                         f"coordinate {coordinate} at t = {t_value:.6g} s (the reduced inertia "
                         "vanishes there, e.g. a dead centre of the driving coordinate)")


class CompiledScene:
    """The generated functions of one scene and the names that give them meaning.

    Attributes: ``coordinates`` (names), ``state_names``, ``param_names`` (user
    parameters, sorted), ``frictions`` (names), ``frozen`` (per friction: index of the
    coordinate it fixes when stuck, or -1), ``stop_labels``, ``output_labels``, ``meta``,
    ``source`` (the generated code), ``key`` (the cache key).
    """

    def __init__(self, meta: dict, source: str, key: str = ""):
        self.meta, self.source, self.key = meta, source, key
        self.coordinates = meta["coordinates"]
        self.dof = len(self.coordinates)
        self.state_names = meta["state_names"]
        self.param_names = meta["param_names"]
        self.frictions = meta["frictions"]
        self.frozen = meta["frozen"]
        self.stop_labels = meta["stop_labels"]
        self.output_labels = meta["output_labels"]
        from .loop_code import LoopSingularError, loop_solve, numeric_jacobian, numeric_minors
        names = compile_source(source, {"SingularMassError": SingularMassError,
                                        "LoopSingularError": LoopSingularError,
                                        "numeric_jacobian": numeric_jacobian,
                                        "_loop_solve": loop_solve,
                                        "_numeric_minors": numeric_minors})
        # Closed loops (empty without): constraint labels, the generated closure
        # functions (see loop_code), and outputs that are loop multipliers.
        self.constraints = meta.get("constraints", [])
        self.independent = meta.get("independent", list(range(self.dof)))
        self.multiplier_outputs = meta.get("multiplier_outputs", {})
        for name in ("multipliers", "closure", "loop_minors", "drift", "linear_terms"):
            setattr(self, name, names.get(name))
        self.rhs = names["rhs"]
        self._jac = names["jac"]
        self.terms = names["terms"]
        self.stops = [names[f"stop{i}"] for i in range(len(self.stop_labels))]
        self.outputs = names["outputs"]
        self.energy = names["energy"]

    # ---------------------------------------------------------------- parameters
    def parameter_vector(self, params: dict, signs=None) -> list:
        """``p`` from a dict of parameter values (keys: symbols or their names).

        All missing parameters are named in one error; NaN or infinite values too.
        """
        by_name = {}
        for key, value in params.items():
            by_name[str(key)] = value
        missing = [n for n in self.param_names if n not in by_name]
        if missing:
            raise ParameterError(f"missing parameter values: {', '.join(missing)} "
                                 f"(the scene needs {', '.join(self.param_names)})")
        values, bad = [], []
        for n in self.param_names:
            try:
                v = float(by_name[n])
            except (TypeError, ValueError):
                raise ParameterError(f"parameter {n} = {by_name[n]!r} is not a number") from None
            if not math.isfinite(v):
                bad.append(f"{n} = {v}")
            values.append(v)
        if bad:
            raise ParameterError(f"parameter values must be finite: {', '.join(bad)}")
        signs = [0.0] * len(self.frictions) if signs is None else list(signs)
        return values + signs

    # ------------------------------------------------------------------ Jacobian
    def jac(self, t_value, y, p):
        """Analytic Jacobian d(dy/dt)/dy of :meth:`rhs` (a ``2n x 2n`` array)."""
        n = self.dof
        if n <= _UNROLLED_LIMIT or self.constraints:
            return np.array(self._jac(t_value, y, p), dtype=float)
        flat = self._jac(t_value, y, p)
        mass = np.array(flat[:n * n]).reshape(n, n)
        forcing = np.array(flat[n * n:n * n + n])
        offset = n * n + n
        mass_derivatives = np.array(flat[offset:offset + n ** 3]).reshape(n, n, n)
        offset += n ** 3
        f_q = np.array(flat[offset:offset + n * n]).reshape(n, n)
        f_u = np.array(flat[offset + n * n:]).reshape(n, n)
        acceleration = np.linalg.solve(mass, forcing)
        a_q = f_q - np.einsum("kij,j->ik", mass_derivatives, acceleration)
        blocks = np.linalg.solve(mass, np.hstack([a_q, f_u]))
        out = np.zeros((2 * n, 2 * n))
        out[:n, n:] = np.eye(n)
        out[n:, :] = blocks
        return out

    def __repr__(self):
        return (f"CompiledScene(states {self.state_names}, parameters {self.param_names}, "
                f"frictions {self.frictions})")


# ------------------------------------------------------------------------- caching
def _cache_dir():
    setting = os.environ.get("MECHDYN_CACHE", "")
    if setting.lower() in ("off", "0", "no", "false"):
        return None
    if setting:
        return Path(setting)
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "mechdyn"


def _generator_hash() -> str:
    """A hash of the modules that shape generated code, so editing them voids the cache."""
    here = Path(__file__).parent
    digest = hashlib.sha256()
    for module in ("derive.py", "codegen.py", "compile.py", "elements.py", "symbols.py",
                   "loop_code.py"):
        digest.update((here / module).read_bytes())
    return digest.hexdigest()[:16]


_GENERATOR = _generator_hash()


def declaration_key(mechanism, scene) -> str:
    """A hash of everything the compiled code depends on."""
    names, rigid = selection(mechanism, scene)
    parts = [__version__, _GENERATOR, [q.func.__name__ for q in mechanism.coordinates]]
    for element in mechanism.elements.values():
        parts.append([type(element).__name__, element.name, list(element.tags),
                      sorted((k, sp.srepr(v)) for k, v in element.expressions().items())])
    parts += [list(names), [list(r) for r in rigid]]
    if mechanism.constraints:
        parts.append([q.func.__name__ for q in mechanism.independent])
    if scene is not None:
        parts.append([sp.srepr(o) if isinstance(o, sp.Basic) else str(o) for o in scene.outputs])
        parts.append([[sp.srepr(c.expression), sp.srepr(c.value), c.direction, repr(c)]
                      for c in scene.until])
    return hashlib.sha256(repr(parts).encode()).hexdigest()[:32]


def compile_scene(mechanism, scene) -> CompiledScene:
    """The compiled functions of ``scene`` on ``mechanism``, from cache when possible."""
    key = declaration_key(mechanism, scene)
    if key in _memory_cache:
        return _memory_cache[key]
    directory = _cache_dir()
    path = directory / f"{key}.json" if directory else None
    compiled = None
    if path is not None and path.is_file():
        try:
            stored = json.loads(path.read_text())
            compiled = CompiledScene(stored["meta"], stored["source"], key)
        except (OSError, ValueError, KeyError, SyntaxError):
            compiled = None          # a damaged entry is rebuilt below
    if compiled is None:
        meta, source = generate(mechanism.equations(scene), scene, mechanism.elements)
        compiled = CompiledScene(meta, source, key)
        if path is not None:
            _store(path, {"meta": meta, "source": source})
    _memory_cache[key] = compiled
    return compiled


def _store(path: Path, data: dict):
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        temporary = path.with_suffix(f".{os.getpid()}.tmp")
        temporary.write_text(json.dumps(data))
        temporary.replace(path)
    except OSError:
        pass                         # a read-only home only costs the warm start


# ---------------------------------------------------------------------- generation
def generate(eqs, scene, elements) -> tuple:
    """Metadata and generated source for the equations ``eqs`` of ``scene``
    (``elements``: the mechanism's elements by name, for outputs)."""
    n = eqs.dof
    frictions = eqs.frictions
    outputs = _outputs(eqs, scene, elements)
    stops = [] if scene is None else [
        (repr(c), eqs.to_plain(c.expression - c.value)) for c in scene.until]
    signs = safe_symbols("s", len(frictions))
    forcing = eqs.smooth_forcing
    for sign, fr in zip(signs, frictions):
        forcing = forcing - sign * fr.magnitude * fr.gradient
    output_exprs = [e for _, e in outputs]
    output_exprs = [_friction_signed(e, eqs, signs) for e in output_exprs]
    everything = [eqs.mass_matrix, forcing, eqs.kinetic_energy, eqs.potential_energy]
    everything += [fr.magnitude for fr in frictions] + [e for _, e in stops] + output_exprs
    everything += [c.expression for c in eqs.constraints]       # a loop's ground length
    known = set(eqs.q) | set(eqs.u) | {t} | set(signs)
    params = sorted(set().union(*(sp.sympify(e).free_symbols for e in everything)) - known,
                    key=lambda s: s.name)
    q_names, u_names = safe_symbols("q", n), safe_symbols("u", n)
    p_names = safe_symbols("p", len(params))
    rename = dict(zip(eqs.q, q_names)) | dict(zip(eqs.u, u_names)) | dict(zip(params, p_names))
    rename[t] = sp.Symbol("t")

    def r(expr):
        return sp.sympify(expr).xreplace(rename)

    coordinates = [str(q) for q in eqs.q]
    state_names = coordinates + [str(u) for u in eqs.u]
    arguments = [str(s) for s in q_names + u_names]
    parameters = [str(s) for s in p_names + signs]
    doc = (f"y = [{', '.join(state_names)}]; "
           f"p = [{', '.join([s.name for s in params] + [f'sign of {fr.name}' for fr in frictions])}]")
    mass = eqs.mass_matrix.xreplace(rename)
    forcing = forcing.xreplace(rename)
    if eqs.constraints:      # closed loops: rhs solves M a = f + G' lambda, G a = -bias
        from .loop_code import loop_sources
        loops = loop_sources(eqs, mass, forcing, rename, arguments, parameters, doc)
        sources = [loops.pop("rhs"), loops.pop("jac"), *loops.values()]
    else:
        sources = [_rhs_source(mass, forcing, n, arguments, parameters, coordinates, doc),
                   _jac_source(mass, forcing, q_names, u_names, arguments, parameters, doc,
                               coordinates)]
    grads = [r(g) for fr in frictions for g in fr.gradient]
    term_exprs = list(mass) + list(forcing) + grads + [r(fr.bias) for fr in frictions] \
        + [r(fr.magnitude) for fr in frictions] + [r(fr.rate) for fr in frictions]
    sources.append(function_source("terms", arguments, parameters, term_exprs,
                                   "return [" + "{}, " * len(term_exprs) + "]", doc))
    for i, (_, expr) in enumerate(stops):
        sources.append(function_source(f"stop{i}", arguments, parameters, [r(expr)],
                                       "return {0}", doc))
    sources.append(function_source("outputs", arguments, parameters,
                                   [r(e) for e in output_exprs],
                                   "return [" + "{}, " * len(output_exprs) + "]", doc))
    sources.append(function_source("energy", arguments, parameters,
                                   [r(eqs.kinetic_energy), r(eqs.potential_energy)],
                                   "return [{0}, {1}]", doc))
    meta = {
        "coordinates": coordinates,
        "state_names": state_names,
        "param_names": [s.name for s in params],
        "frictions": [fr.name for fr in frictions],
        "frozen": [_frozen_index(fr) for fr in frictions],
        "stop_labels": [label for label, _ in stops],
        "output_labels": [label for label, _ in outputs],
        "eliminated": {c.func.__name__: str(e) for c, e in eqs.eliminated.items()},
        "elements": list(eqs.elements), "excluded": list(eqs.excluded),
        "rigid": list(eqs.rigid),
        "time_functions": [c.func.__name__ for c in eqs.coordinates],
    }
    if eqs.constraints:
        meta["constraints"] = [c.name for c in eqs.constraints]
        meta["loops"] = [next(n for n, e in elements.items() if isinstance(e, Constraint)
                              and c.name in e.labels) for c in eqs.constraints]
        meta["independent"] = [eqs.q.index(q) for q in eqs.independent]
        meta["multiplier_outputs"] = {label: meta["constraints"].index(label)
                                      for label, _ in outputs
                                      if label in meta["constraints"]}
    return meta, "\n".join(sources)


def _frozen_index(friction) -> int:
    """The coordinate a stuck friction fixes, when its gradient is one constant entry."""
    nonzero = [i for i, g in enumerate(friction.gradient) if g != 0]
    if len(nonzero) == 1 and friction.gradient[nonzero[0]].is_number:
        return nonzero[0]
    return -1


def _friction_signed(expr, eqs, signs):
    """Replace ``sign(rate)`` of each friction by its run-time sign parameter."""
    return sp.sympify(expr).xreplace({sp.sign(fr.rate): s for fr, s in zip(eqs.frictions, signs)})


def _outputs(eqs, scene, elements) -> list:
    """``(label, plain expression)`` for each requested output."""
    if scene is None:
        return []
    result = []
    for item in scene.outputs:
        if isinstance(item, str):
            label = item
            if item.startswith("power:"):
                name = item[len("power:"):]
                if name not in eqs.powers:
                    raise SceneError(f"scene {scene.name!r}: output {item!r}: no load "
                                     f"{name!r} in the scene (loads: {sorted(eqs.powers)})")
                result.append((label, eqs.powers[name]))
                continue
            if isinstance(elements.get(item), Constraint):   # its multipliers (simulate)
                result += [(component, sp.S.Zero) for component in elements[item].labels]
                continue
            result.append((label, _element_output(eqs, scene, item, elements)))
        else:
            expr = sp.sympify(item) if isinstance(item, sp.Basic) else None
            if expr is None:
                raise SceneError(f"scene {scene.name!r}: output {item!r} is neither an element "
                                 "name, 'power:NAME', nor a sympy expression")
            result.append((str(item), eqs.to_plain(expr)))
    return result


def _element_output(eqs, scene, name, elements):
    element = elements.get(name) if name in eqs.elements else None
    if element is None:
        raise SceneError(f"scene {scene.name!r}: output {name!r} is not an element of the "
                         f"scene (elements: {list(eqs.elements)})")
    if isinstance(element, Spring):
        return eqs.to_plain(element.k * element.stretch)
    if isinstance(element, Damper):
        stretch = eqs.to_plain(element.stretch)
        rate = sum((sp.diff(stretch, q) * u for q, u in zip(eqs.q, eqs.u)), sp.S.Zero) \
            + sp.diff(stretch, t)
        return eqs.to_plain(element.c) * rate
    if isinstance(element, Load):
        return eqs.to_plain(element.value)
    if isinstance(element, Friction):
        fr = next(f for f in eqs.frictions if f.name == name)
        return -fr.magnitude * sp.sign(fr.rate)
    raise SceneError(f"scene {scene.name!r}: output {name!r}: a {type(element).__name__.lower()}"
                     " has no single force to record; ask for an expression instead")


def _cholesky_lines(n, m, coordinates):
    """Source lines factoring ``M = L L'`` (``m[(i, j)]``: names of the lower entries,
    ``None`` where the entry is structurally zero); a pivot that is not positive raises
    SingularMassError naming its coordinate. Returns the lines and the set of entries of
    ``L`` that are structurally zero (a diagonal mass matrix costs one division each)."""
    lines, zero = [], set()
    for i in range(n):
        for j in range(i):
            products = [f"L{i}{k} * L{j}{k}" for k in range(j)
                        if (i, k) not in zero and (j, k) not in zero]
            if m[(i, j)] is None and not products:
                zero.add((i, j))
                continue
            acc = " - ".join([m[(i, j)] or "0.0"] + products)
            lines.append(f"L{i}{j} = ({acc}) / L{j}{j}")
        products = [f"L{i}{k} * L{i}{k}" for k in range(i) if (i, k) not in zero]
        lines.append(f"L{i}{i} = {' - '.join([m[(i, i)] or '0.0'] + products)}")
        lines.append(f"if not L{i}{i} > 0: raise SingularMassError({coordinates[i]!r}, t, y)")
        lines.append(f"L{i}{i} = sqrt(L{i}{i})")
    return lines, zero


def _solve_lines(n, rhs, out, zero):
    """Source lines solving ``L L' out = rhs`` with the factor of :func:`_cholesky_lines`
    (``rhs``: n expressions; ``out``: the prefix of the n result names)."""
    lines = []
    for i in range(n):
        terms = [f"L{i}{k} * {out}z{k}" for k in range(i) if (i, k) not in zero]
        lines.append(f"{out}z{i} = ({' - '.join([rhs[i]] + terms)}) / L{i}{i}")
    for i in reversed(range(n)):
        terms = [f"L{k}{i} * {out}{k}" for k in range(i + 1, n) if (k, i) not in zero]
        lines.append(f"{out}{i} = ({' - '.join([f'{out}z{i}'] + terms)}) / L{i}{i}")
    return lines


def _lower_names(mass, names):
    """Names of the lower entries of ``mass`` (``None`` for structural zeros), consuming
    ``names`` only for the entries that are computed."""
    n = mass.shape[0]
    return {(i, j): (None if mass[i, j] == 0 else next(names)) for i, j in _lower(n)}


def _lower(n):
    return [(i, j) for i in range(n) for j in range(i + 1)]


def _rhs_source(mass, forcing, n, arguments, parameters, coordinates, doc):
    """dy/dt = [u, M^-1 f] with an unrolled Cholesky solve (numpy beyond the limit)."""
    if n > _UNROLLED_LIMIT:
        exprs = list(mass) + list(forcing)
        body = ("return _solve([" + "{}, " * (n * n) + "], [" + "{}, " * n + "], y, "
                f"{n}, t, {coordinates!r})")
        return function_source("rhs", arguments, parameters, exprs, body, doc) + _NUMPY_SOLVE
    names = iter(f"_e{k}" for k in range(n * n + n))
    m = _lower_names(mass, names)
    exprs = [mass[i, j] for (i, j), name in m.items() if name is not None] + list(forcing)
    f = [next(names) for _ in range(n)]
    if n == 1:
        checks = [f"if not {m[(0, 0)]} > 0: raise SingularMassError({coordinates[0]!r}, t, y)"]
        body = f"return [{arguments[1]}, {f[0]} / {m[(0, 0)]}]"
        return function_source("rhs", arguments, parameters, exprs, body, doc, checks)
    checks, zero = _cholesky_lines(n, m, coordinates)
    checks += _solve_lines(n, f, "a", zero)
    speeds = ", ".join(arguments[n:])
    body = f"return [{speeds}, {', '.join(f'a{i}' for i in range(n))}]"
    return function_source("rhs", arguments, parameters, exprs, body, doc, checks)


_NUMPY_SOLVE = '''
def _solve(mass, forcing, y, n, t, coordinates):
    import numpy
    try:
        a = numpy.linalg.solve(numpy.reshape(mass, (n, n)), forcing)
    except numpy.linalg.LinAlgError:
        raise SingularMassError(", ".join(coordinates), t, y) from None
    return list(y[n:]) + list(a)
'''


def _jac_source(mass, forcing, q_names, u_names, arguments, parameters, doc, coordinates):
    """The analytic Jacobian ``[[0, I], [da/dq, da/du]]`` with ``da/dq = M^-1 (df/dq -
    dM/dq a)`` and ``da/du = M^-1 df/du``: scalar code with the unrolled Cholesky factor
    up to the unrolling limit; beyond it the pieces, assembled with numpy."""
    n = len(q_names)
    if n == 1:
        q, u = q_names[0], u_names[0]
        exprs = [mass[0, 0], forcing[0], sp.diff(mass[0, 0], q), sp.diff(forcing[0], q),
                 sp.diff(forcing[0], u)]
        body = "a = {1} / {0}; return [[0.0, 1.0], [({3} - {2} * a) / {0}, {4} / {0}]]"
        return function_source("jac", arguments, parameters, exprs, body, doc)
    if n > _UNROLLED_LIMIT:
        exprs = list(mass) + list(forcing)
        exprs += [sp.diff(mass[i, j], qk) for qk in q_names for i in range(n) for j in range(n)]
        exprs += [sp.diff(forcing[i], qk) for i in range(n) for qk in q_names]
        exprs += [sp.diff(forcing[i], uk) for i in range(n) for uk in u_names]
        return function_source("jac", arguments, parameters, exprs,
                               "return [" + "{}, " * len(exprs) + "]", doc)
    names = iter(f"_e{k}" for k in range(2 * n ** 3 + 4 * n * n))
    m = _lower_names(mass, names)
    exprs = [mass[i, j] for (i, j), name in m.items() if name is not None] + list(forcing)
    f = [next(names) for _ in range(n)]
    dm, f_q, f_u = [], [], []                      # f_q[k][i] = df_i/dq_k
    for qk in q_names:
        block = [[sp.diff(mass[i, j], qk) for j in range(n)] for i in range(n)]
        dm.append([[None if e == 0 else next(names) for e in row] for row in block])
        exprs += [e for row in block for e in row if e != 0]
    for derivatives, variables in ((f_q, q_names), (f_u, u_names)):
        for v in variables:
            column = [sp.diff(forcing[i], v) for i in range(n)]
            derivatives.append([None if e == 0 else next(names) for e in column])
            exprs += [e for e in column if e != 0]
    lines, zero = _cholesky_lines(n, m, coordinates)
    lines += _solve_lines(n, f, "a", zero)
    for k in range(n):
        column = [" - ".join([f_q[k][i] or "0.0"] + [f"{dm[k][i][j]} * a{j}" for j in range(n)
                                                      if dm[k][i][j] is not None])
                  for i in range(n)]
        lines += _solve_lines(n, [f"({c})" for c in column], f"q{k}_", zero)
        lines += _solve_lines(n, [f_u[k][i] or "0.0" for i in range(n)], f"u{k}_", zero)
    rows = [[("1.0" if j == n + i else "0.0") for j in range(2 * n)] for i in range(n)]
    rows += [[f"q{k}_{i}" for k in range(n)] + [f"u{k}_{i}" for k in range(n)]
             for i in range(n)]
    body = "return [" + ", ".join("[" + ", ".join(r) + "]" for r in rows) + "]"
    return function_source("jac", arguments, parameters, exprs, body, doc, lines)

"""The errors mechdyn raises; each message names the culprit (element, parameter, state).

The errors of this module, and those other modules define (``ModelFileError``,
``AnalyticError``, ...), derive from :class:`MechdynError`, so a script can catch them
in one place. Warnings derive from :class:`MechdynWarning`.
"""

import difflib

__all__ = ["MechdynError", "MechdynWarning", "DeclarationError", "DerivationError", "SceneError",
           "ParameterError", "SimulationError", "OutputError", "DependencyError", "did_you_mean"]


def did_you_mean(name, choices) -> str:
    """``" (did you mean X?)"`` for the choice closest to a misspelt ``name`` (the same
    letters swapped first, then the most similar), else "".

    >>> did_you_mean("startp", ["startup", "braking"]), did_you_mean("rmp", ["rps", "rpm"])
    (' (did you mean startup?)', ' (did you mean rpm?)')
    """
    choices = [str(c) for c in choices]
    swapped = [c for c in choices if sorted(c) == sorted(str(name)) and c != str(name)]
    close = swapped or difflib.get_close_matches(str(name), choices, n=1)
    return f" (did you mean {close[0]}?)" if close else ""


class MechdynError(Exception):
    """Base class of every mechdyn error.

    Examples
    --------
    One ``except`` catches every error mechdyn raises:

    >>> import mechdyn as md
    >>> try:
    ...     md.coordinate("2nd")
    ... except md.MechdynError as error:
    ...     print(type(error).__name__)
    DeclarationError
    """


class MechdynWarning(UserWarning):
    """Base class of mechdyn's warnings (e.g. a cache directory that is not used).

    Examples
    --------
    Turn them into errors, or silence them, as one category:

    >>> import warnings, mechdyn as md
    >>> issubclass(md.MechdynWarning, UserWarning)
    True
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("error", md.MechdynWarning)
    """


class DeclarationError(MechdynError, ValueError):
    """A mechanism or element declared wrongly (names, expressions, values).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> disc = md.Mechanism("disc", [phi])
    >>> try:
    ...     disc.link("disc", J=-1, angle=phi)
    ... except md.DeclarationError as error:
    ...     print(type(error).__name__)
    DeclarationError
    """


class DerivationError(MechdynError, ValueError):
    """The equations cannot be formed (no inertia in a coordinate, wrong DOF count).

    Examples
    --------
    >>> import mechdyn as md
    >>> x = md.coordinate("x")
    >>> massless = md.Mechanism("massless", [x])
    >>> _ = massless.load("push", 1, along=x)
    >>> try:
    ...     massless.equations()
    ... except md.DerivationError as error:
    ...     print(error)
    mechanism 'massless': no inertia in coordinate x: no link's mass or moment of inertia moves with it (give a link m or J that moves with it, or make its spring rigid in the scene)
    """


class SceneError(MechdynError, ValueError):
    """A scene that does not fit its mechanism (unknown effect, missing initial value).

    Examples
    --------
    >>> import mechdyn as md
    >>> phi = md.coordinate("phi")
    >>> try:
    ...     md.Scene("spin", initial={phi: 0, md.speed(phi): 1}, t_end=float("nan"))
    ... except md.SceneError as error:
    ...     print(type(error).__name__)
    SceneError
    """


class ParameterError(MechdynError, ValueError):
    """Missing, unknown or invalid parameter values.

    Examples
    --------
    Parameter values are checked before anything is derived or compiled:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> P = model.param_symbol("P")
    >>> try:
    ...     model.mechanism.simulate(model.scenes["braking"], {**model.params, P: -20})
    ... except md.ParameterError as error:
    ...     print(type(error).__name__)
    ParameterError
    """


class SimulationError(MechdynError, RuntimeError):
    """The integration failed; ``partial`` holds the result computed up to the failure.

    Examples
    --------
    A run stopped by its step budget keeps what it computed:

    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> try:
    ...     model.mechanism.simulate(model.scenes["braking"], model.params, max_steps=2)
    ... except md.SimulationError as error:
    ...     print(type(error).__name__, error.partial.reason.split(" of ")[0])
    SimulationError failed: integration stopped at t = 50 s
    """

    def __init__(self, message, partial=None):
        super().__init__(message)
        self.partial = partial


class OutputError(MechdynError, OSError):
    """A file could not be written (disk full, no permission); the message names it and
    the old file, if any, is left as it was.

    Examples
    --------
    >>> import mechdyn as md
    >>> model = md.load_model("shoe_brake")
    >>> res = model.mechanism.simulate(model.scenes["braking"], model.params)
    >>> try:
    ...     res.to_csv("/no/such/folder/brake.csv")
    ... except md.OutputError as error:
    ...     print(error)
    cannot write /no/such/folder/brake.csv: No such file or directory; nothing written
    """


class DependencyError(MechdynError, RuntimeError):
    """An installed dependency lacks an internal that mechdyn relies on where the
    library has no public API for it (numba's function addresses, scipy's error-norm
    hook and dense-output fields): a release outside the tested range
    (docs/guide/dependencies.md). The message names the package, its version and what is missing.

    Examples
    --------
    >>> import mechdyn as md
    >>> error = md.DependencyError("scipy", "the attribute RK45.example_hook", "a test")
    >>> print(error)                                  # doctest: +ELLIPSIS
    scipy ... has no the attribute RK45.example_hook, which mechdyn uses for a test: ...
    """

    def __init__(self, package, missing, needed_for):
        import importlib.metadata
        try:
            version = importlib.metadata.version(package)
        except importlib.metadata.PackageNotFoundError:      # pragma: no cover
            version = "?"
        super().__init__(f"{package} {version} has no {missing}, which mechdyn uses for "
                         f"{needed_for}: this {package} release is outside the tested range "
                         f"(see pyproject.toml); install a tested one")
        self.package, self.missing = package, missing


"""The registries of the benchmark: estimators and predictors, by name.

An estimator is a function ``run(ctx, **options) -> comcore.Estimate`` of a
:class:`TrialContext`; register one with :func:`register_estimator` and it can
be named on the command line (``--estimators alg1 mine``), with options
(``"alg1(threshold=0.2)"``). A predictor is a factory ``make(ctx) ->
comcore.Predictor``; the learned ones are conditioned on prior pushes run in
the simulator, which the trial runner draws and counts.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

import comcore

__all__ = [
    "ESTIMATORS",
    "GROUPS",
    "PREDICTORS",
    "EstimatorSpec",
    "PredictorSpec",
    "TrialContext",
    "option_groups",
    "parse_estimator",
    "register_estimator",
    "split_estimators",
]


#: The active estimators' option groups and the keyword each is passed as.
GROUPS = {"likelihood": comcore.Likelihood, "stop": comcore.StopRule, "choice": comcore.PushChoice}


def option_groups(**flat) -> dict[str, Any]:
    """The option groups (``likelihood``, ``stop``, ``choice``) from flat option names.

    For labels, configuration files and command lines: ``option_groups(max_pushes=3,
    pusher_error=0.002)`` gives ``{"likelihood": Likelihood(pusher_error=0.002),
    "stop": StopRule(max_pushes=3)}``, to pass as ``**`` to
    :func:`comcore.estimate_active` or :class:`comcore.ActiveSession`. Only the
    groups named are returned.

    Raises
    ------
    TypeError
        On a name that belongs to no group (the valid names are listed).

    Examples
    --------
    >>> sorted(option_groups(max_pushes=3, cone=0.2))
    ['choice', 'stop']
    """
    group_of = {f.name: key for key, cls in GROUPS.items() for f in dataclasses.fields(cls)}
    unknown = sorted(set(flat) - set(group_of))
    if unknown:
        raise TypeError(f"unknown option(s) {unknown}; the options are {sorted(group_of)}")
    out: dict[str, Any] = {}
    for keyword, cls in GROUPS.items():
        mine = {k: v for k, v in flat.items() if group_of[k] == keyword}
        if mine:
            out[keyword] = cls(**mine)
    return out


@dataclass(frozen=True)
class TrialContext:
    """Everything an estimator may look at in one trial.

    Attributes
    ----------
    object, friction : str
        Benchmark object and friction class.
    trial : int
        Index of the trial.
    simulator : simulators.PushSimulator
        The true object (estimators must touch it only through ``push``).
    mask : comcore.Mask
        The object as the camera sees it.
    candidates : numpy.ndarray, shape (n, 4)
        The trial's random candidate pushes (pixels).
    motions : numpy.ndarray, shape (n, 3), or None
        The predictor's motions of the candidates (``None`` if no estimator needs them).
    priors : tuple of (Action, Motion)
        Pushes run in the simulator to condition a learned predictor.
    rng : numpy.random.Generator
        This estimator's own generator (seeded from the trial and its name).
    push : callable
        ``push(action) -> Motion`` on the true object from its initial pose;
        every call is counted as a real push.
    robot : callable or None
        ``robot(**options) -> simulators.SimulatedRobot``: the trial's object as a
        robot that never resets it, under the trial's condition (pusher error,
        camera noise, engine); ``options`` override the condition's. Every push the
        robot executes is counted as a real push, and an estimate of a run that made
        a robot is scored in the robot's camera frame (``robot.true_com_px``).
    condition : object or None
        The realism condition of the trial (:class:`comcore.bench.Condition`);
        ``None`` for the plain benchmark.
    """

    object: str
    friction: str
    trial: int
    simulator: Any
    mask: comcore.Mask
    candidates: np.ndarray
    motions: np.ndarray | None
    priors: tuple = ()
    rng: np.random.Generator = field(default_factory=np.random.default_rng)
    push: Callable[[comcore.Action], comcore.Motion] | None = None
    robot: Callable[..., Any] | None = None
    condition: Any = None


@dataclass(frozen=True)
class EstimatorSpec:
    """A registered estimator.

    Attributes
    ----------
    name : str
    run : callable
        ``run(ctx: TrialContext, **options) -> comcore.Estimate``.
    description : str
    uses_motions : bool
        ``True``: it works on the predicted motions of the candidates and its
        real pushes are ``len(Estimate.used)`` (plus the predictor's priors).
        ``False``: it ignores the predictor (``ctx.motions`` may be ``None``);
        its real pushes are the calls it made to ``ctx.push``.
    requires : callable
        ``requires() -> str | None``: why it cannot run in this build, or ``None``.
    resets : bool
        ``True``: it needs the object put back between pushes (every motion from
        the initial pose); the ``no-reset`` condition does not run it.
    """

    name: str
    run: Callable[..., comcore.Estimate]
    description: str
    uses_motions: bool = True
    requires: Callable[[], str | None] = lambda: None
    resets: bool = True


@dataclass(frozen=True)
class PredictorSpec:
    """A registered motion predictor.

    Attributes
    ----------
    name : str
    make : callable
        ``make(ctx: TrialContext) -> comcore.Predictor`` (``ctx.motions`` is ``None``).
    prior_pushes : int
        Real pushes run in the simulator to condition it (12 for the learned ones).
    pushes_object : bool
        Its predictions are pushes of the true object (the oracle): candidates
        are predicted one by one and those the simulator refuses are redrawn.
    requires : callable
        ``requires() -> str | None``: why it cannot run in this build, or ``None``.
    """

    name: str
    make: Callable[[TrialContext], Any]
    prior_pushes: int = 0
    requires: Callable[[], str | None] = lambda: None
    pushes_object: bool = False


ESTIMATORS: dict[str, EstimatorSpec] = {}
PREDICTORS: dict[str, PredictorSpec] = {}
_NAME = re.compile(r"^[A-Za-z][\w.-]*$")


def register_estimator(
    name: str,
    run: Callable[..., comcore.Estimate],
    *,
    description: str = "",
    uses_motions: bool = True,
    requires: Callable[[], str | None] | None = None,
    replace: bool = False,
    resets: bool = True,
) -> EstimatorSpec:
    """Add an estimator to :data:`ESTIMATORS` (see :class:`EstimatorSpec`).

    Examples
    --------
    >>> import comcore
    >>> from comcore.bench import ESTIMATORS, register_estimator
    >>> spec = register_estimator(
    ...     "first-push-line", lambda ctx: comcore.estimate_progressive(
    ...         ctx.mask, ctx.candidates[:1], ctx.motions[:1]),
    ...     description="Alg. 2 with one push")
    >>> "first-push-line" in ESTIMATORS
    True
    >>> del ESTIMATORS["first-push-line"]
    """
    if not isinstance(name, str) or not _NAME.match(name):
        raise ValueError(f"name must be a word like 'alg1' or 'my-estimator', got {name!r}")
    if not callable(run):
        raise TypeError(f"run must be callable as run(ctx, **options), got {type(run).__name__}")
    if name in ESTIMATORS and not replace:
        raise ValueError(f"estimator {name!r} is already registered (pass replace=True)")
    spec = EstimatorSpec(
        name, run, description, bool(uses_motions), requires or (lambda: None), bool(resets)
    )
    ESTIMATORS[name] = spec
    return spec


def split_estimators(text: str) -> list[str]:
    """Split ``"alg1, alg1(threshold=0.2, length_scale=3),alg2"`` at top-level commas.

    Examples
    --------
    >>> split_estimators("alg1, alg1(threshold=0.2, length_scale=3),alg2")
    ['alg1', 'alg1(threshold=0.2, length_scale=3)', 'alg2']
    """
    out, depth, current = [], 0, ""
    for char in text:
        depth += (char == "(") - (char == ")")
        if char == "," and depth == 0:
            out.append(current.strip())
            current = ""
        else:
            current += char
    out.append(current.strip())
    return [item for item in out if item]


def parse_estimator(label: str) -> tuple[EstimatorSpec, dict[str, Any]]:
    """The registered estimator and keyword options named by ``label``.

    ``label`` is a registered name, optionally followed by Python keyword
    arguments with literal values: ``"alg1(threshold=0.2, length_scale=3.0)"``.

    Examples
    --------
    >>> spec, options = parse_estimator("alg1(threshold=0.2)")
    >>> spec.name, options
    ('alg1', {'threshold': 0.2})
    >>> parse_estimator("alg9")
    Traceback (most recent call last):
    ...
    ValueError: estimators: unknown estimator 'alg9'; registered: active, ...
    """
    name, options = parse_call(label, "estimators", ESTIMATORS)
    return ESTIMATORS[name], options


def parse_call(label: str, what: str, known: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """``"name(key=literal, ...)"`` as ``(name, options)``; ``name`` must be in ``known``.

    Errors name ``what`` (the option being parsed, e.g. ``"estimators"``).
    """
    match = re.fullmatch(r"\s*([\w.-]+)\s*(?:\((.*)\))?\s*", label or "")
    names = ", ".join(sorted(known))
    if not match:
        raise ValueError(f"{what}: cannot parse {label!r}; expected name or name(key=value)")
    name, arguments = match.group(1), match.group(2)
    if name not in known:
        raise ValueError(f"{what}: unknown {what.rstrip('s')} {name!r}; registered: {names}")
    options: dict[str, Any] = {}
    if arguments and arguments.strip():
        try:
            call = ast.parse(f"f({arguments})", mode="eval").body
            if not isinstance(call, ast.Call) or call.args:
                raise ValueError("only keyword arguments are allowed")
            options = {kw.arg: ast.literal_eval(kw.value) for kw in call.keywords}
            if None in options:
                raise ValueError("**kwargs is not allowed")
        except (SyntaxError, ValueError) as e:
            raise ValueError(
                f"{what}: bad options in {label!r} ({e}); expected name(key=literal, ...)"
            ) from e
    return name, options


def missing(module: str, attribute: str, install: str | None = None) -> Callable[[], str | None]:
    """A ``requires`` check: the reason ``module.attribute`` cannot be used, or ``None``.

    ``install`` (e.g. ``"pip install comcore[anp]"``) is appended to the reason
    when the import fails.
    """

    def check() -> str | None:
        try:
            getattr(importlib.import_module(module), attribute)
        except (ImportError, AttributeError) as e:
            reason = f"{module}.{attribute} is not available ({type(e).__name__}: {e})"
            return f"{reason}; {install}" if install else reason
        return None

    return check


def requirements(*checks: Callable[[], str | None]) -> Callable[[], str | None]:
    """Combine ``requires`` checks: the first failure's reason, or ``None``."""

    def check() -> str | None:
        return next((reason for reason in (c() for c in checks) if reason), None)

    return check

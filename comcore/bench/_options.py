"""Estimator options checked against the estimator's signature before any trial runs.

``"alg2(min_scor=0.5)"`` must fail at once, not as an error row in every trial.
A registered ``run(ctx, k=2)`` is checked against its own parameters; one that
takes ``**options`` and hands them on (the built-ins do) is checked against the
parameters of the function they reach (the active estimators': the fields of the
option groups, which :func:`comcore.bench.option_groups` builds from flat names). Where the chain
ends in a ``**options`` nobody can resolve, the options are accepted as they are.
"""

from __future__ import annotations

import difflib
import inspect
from collections.abc import Callable, Sequence

from ._registry import GROUPS, EstimatorSpec, option_groups, parse_estimator

__all__ = ["accepted_options", "check_estimator_options", "check_estimator_values"]

def _forwarded_to(spec: EstimatorSpec) -> Sequence[Callable | tuple | None]:
    """The functions a built-in estimator hands its ``**options`` to, in order.

    A tuple of callables stands for one step whose options are any of theirs (the
    option groups: ``option_groups(**options)`` builds one group of each).
    """
    import comcore

    from . import _builtins

    if getattr(spec.run, "__module__", None) != _builtins.__name__:
        return ()
    groups = tuple(GROUPS.values())  # option_groups(**options): the fields of the groups
    chains: dict[str, Sequence[Callable | tuple | None]] = {
        "_alg1": (comcore.estimate_heatmap,),
        "_alg2": (comcore.estimate_progressive,),
        "_alg2_rotation": (comcore.estimate_progressive,),
        "_active": (groups,),
        "_active_vt": (getattr(_builtins, "_active", None), groups),
        "_active_robot": (groups,),
    }
    return chains.get(getattr(spec.run, "__name__", ""), ())


def _parameters(func: Callable | tuple, skip_first: bool) -> tuple[set[str], bool] | None:
    """Keyword parameters with defaults (or all after the first), and whether ``**`` is taken."""
    if isinstance(func, tuple):  # one step, any of their options
        found = [_parameters(f, skip_first) for f in func]
        if any(f is None for f in found):
            return None
        return set().union(*(f[0] for f in found)), any(f[1] for f in found)  # type: ignore[index]
    try:
        params = list(inspect.signature(func).parameters.values())
    except (TypeError, ValueError):  # a builtin or C function without a signature
        return None
    if skip_first and params:
        params = params[1:]
    kinds = (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY)
    names = {
        p.name
        for p in params
        if p.kind in kinds and (skip_first or p.default is not inspect.Parameter.empty)
    }
    return names, any(p.kind is inspect.Parameter.VAR_KEYWORD for p in params)


def accepted_options(spec: EstimatorSpec) -> set[str] | None:
    """The option names ``spec`` accepts, or ``None`` if it accepts any.

    Examples
    --------
    >>> from comcore.bench import ESTIMATORS
    >>> "min_score" in accepted_options(ESTIMATORS["alg2"])
    True
    >>> accepted_options(ESTIMATORS["centroid"])
    set()
    """
    found = _parameters(spec.run, skip_first=True)
    if found is None:
        return None
    names, forwards = found
    for target in _forwarded_to(spec):
        if not forwards:
            break
        if target is None:
            return None
        found = _parameters(target, skip_first=False)
        if found is None:
            return None
        more, forwards = found
        names |= more
    return None if forwards else names


def check_estimator_options(label: str) -> None:
    """Raise ValueError if ``label``'s options are not parameters of its estimator.

    Examples
    --------
    >>> check_estimator_options("alg2(min_score=0.5)")
    >>> check_estimator_options("alg2(min_scor=0.5)")
    Traceback (most recent call last):
    ...
    ValueError: estimators: 'alg2(min_scor=0.5)': alg2 has no option min_scor (did you mean min_score?); its options: area_ratio, band, min_rotation, min_score, mu, pusher_radius, selection, target_radius
    """  # noqa: E501
    spec, options = parse_estimator(label)
    accepted = accepted_options(spec)
    if accepted is None:
        return
    unknown = [name for name in options if name not in accepted]
    if not unknown:
        return
    hints = [difflib.get_close_matches(name, sorted(accepted), n=1) for name in unknown]
    guess = "; ".join(f"did you mean {h[0]}?" for h in hints if h)
    listed = ", ".join(sorted(accepted)) or "none"
    raise ValueError(
        f"estimators: {label!r}: {spec.name} has no option {', '.join(unknown)}"
        f"{f' ({guess})' if guess else ''}; its options: {listed}"
    )


def _probe():
    """A 10 x 10 px square with two pushes and their motions: enough to build Alg. 1 and 2."""
    import numpy as np

    import comcore

    mask = comcore.Mask(np.pad(np.ones((10, 10), bool), 4))
    actions = comcore.sample_pushes(mask, 2, rng=0)
    return mask, actions, np.array([[0.1, 1.0, 0.0], [-0.1, 1.0, 0.0]])


#: ``active-robot``'s own options (the rest go to the option groups).
_ROBOT_OPTIONS = (
    "observe",
    "motion_noise",
    "pusher_error",
    "mask_noise",
    "camera_margin",
    "frames",
    "executed",
    "frame_rate",
)


def _check_active(options: dict, robot: bool = False) -> None:
    """Raise for a value the active estimators refuse (their own options, then the groups)."""
    from . import _builtins

    rest = dict(options)
    if rest.get("model", "default") not in _builtins.MODELS:
        raise ValueError(f"model must be one of {_builtins.MODELS}, got {rest['model']!r}")
    rest.pop("model", None)
    if robot:
        observe = rest.get("observe")
        if observe is not None and observe not in _builtins.OBSERVATIONS:
            raise ValueError(f"observe must be one of {_builtins.OBSERVATIONS}, got {observe!r}")
        for name in _ROBOT_OPTIONS:
            rest.pop(name, None)
    elif rest.pop("candidates", "own") not in ("trial", "own"):
        raise ValueError(f"candidates must be 'trial' or 'own', got {options['candidates']!r}")
    option_groups(**rest)


def _value_check(spec: EstimatorSpec) -> Callable[[dict], object] | None:
    """What builds a built-in estimator's options without a trial (``None``: not built-in)."""
    import comcore

    from . import _builtins

    if getattr(spec.run, "__module__", None) != _builtins.__name__:
        return None

    def alg(function, extra=None):
        return lambda options: function(*_probe(), **{**(extra or {}), **options})

    checks: dict[str, Callable[[dict], object]] = {
        "_alg1": alg(comcore.estimate_heatmap),
        "_alg2": alg(comcore.estimate_progressive),
        "_alg2_rotation": alg(comcore.estimate_progressive, {"selection": "rotation"}),
        "_active": _check_active,
        "_active_vt": _check_active,
        "_active_robot": lambda options: _check_active(options, robot=True),
    }
    return checks.get(getattr(spec.run, "__name__", ""))


def check_estimator_values(label: str) -> None:
    """Raise ValueError if a built-in estimator refuses one of ``label``'s option values.

    The estimator is built with its options on a small probe object before any
    trial runs, so a bad value stops the benchmark at once instead of failing
    every trial. Registered estimators other than the built-ins are not probed.

    Examples
    --------
    >>> check_estimator_values("alg1(threshold=0.2)")
    >>> check_estimator_values("alg1(threshold=2)")
    Traceback (most recent call last):
    ...
    ValueError: estimators: 'alg1(threshold=2)': threshold must be in [0, 1], got 2.0
    """
    spec, options = parse_estimator(label)
    check = _value_check(spec)
    if check is None:
        return
    try:
        check(options)
    except (TypeError, ValueError) as e:
        raise ValueError(f"estimators: {label!r}: {e}") from e

"""The option groups from flat names: :func:`option_groups`, and the one shim for old keywords.

``estimate_active(mask, push, max_pushes=3)`` (the flat keywords of earlier
releases) still works for one release: :func:`resolve_groups` is the one shim
that accepts them, with a :class:`DeprecationWarning` saying which group to pass
instead. :func:`option_groups` builds the groups from flat names without a
warning, for configuration files and command lines (``comcore bench`` labels).
"""

from __future__ import annotations

import dataclasses
import inspect
import warnings
from typing import Any

from ._options import Likelihood, PushChoice, StopRule

__all__ = ["GROUPS", "option_groups", "resolve_groups"]

#: The groups and the keyword each is passed as.
GROUPS = {"likelihood": Likelihood, "stop": StopRule, "choice": PushChoice}
#: Which group each flat option name belongs to.
_GROUP_OF = {
    f.name: keyword for keyword, cls in GROUPS.items() for f in dataclasses.fields(cls)
}


def _group_of(name: str) -> str:
    """The group keyword a flat name belongs to (a group keyword is its own)."""
    return name if name in GROUPS else _GROUP_OF[name]


def option_groups(**flat) -> dict[str, Any]:
    """The option groups (``likelihood``, ``stop``, ``choice``) from flat option names.

    For configuration files and command lines: ``option_groups(max_pushes=3,
    pusher_error=0.002)`` gives ``{"likelihood": Likelihood(pusher_error=0.002),
    "stop": StopRule(max_pushes=3)}``, to pass as ``**`` to an entry point. Only
    the groups named are returned.

    Raises
    ------
    TypeError
        On a name that belongs to no group (the valid names are listed).

    Examples
    --------
    >>> import comcore
    >>> sorted(comcore.active.option_groups(max_pushes=3, cone=0.2))
    ['choice', 'stop']
    """
    unknown = sorted(set(flat) - set(_GROUP_OF))
    if unknown:
        if "translation_noise" in unknown:
            raise TypeError(
                "translation_noise (pixels) was removed: pass "
                "likelihood=comcore.Likelihood(translation_error=(metres, relative))"
            )
        if "bootstrap" in unknown:
            raise TypeError(
                "bootstrap is estimate_posterior's alone (it bags a recording's region); a "
                "session's region is its posterior's own"
            )
        raise TypeError(f"unknown option(s) {unknown}; the options are {sorted(_GROUP_OF)}")
    out: dict[str, Any] = {}
    for keyword, cls in GROUPS.items():
        mine = {k: v for k, v in flat.items() if _GROUP_OF[k] == keyword}
        if mine:
            out[keyword] = cls(**mine)
    return out


def _group_signature() -> inspect.Signature:
    """``option_groups``'s signature: every group's fields, keyword-only, with their defaults."""
    return inspect.Signature(
        [
            inspect.Parameter(f.name, inspect.Parameter.KEYWORD_ONLY, default=f.default)
            for cls in GROUPS.values()
            for f in dataclasses.fields(cls)
        ]
    )


option_groups.__signature__ = _group_signature()  # type: ignore[attr-defined]


def resolve_groups(
    caller: str, groups: dict[str, Any], flat: dict[str, Any], *, stacklevel: int = 3
) -> dict[str, Any]:
    """The option groups an entry point runs with: the one shim for flat keywords.

    ``groups`` maps each keyword the caller takes (``"likelihood"``, ``"stop"``,
    ``"choice"``) to what the user passed (a group or None: the defaults).
    ``flat`` holds the flat keywords of earlier releases: each replaces its
    field in its group (the group the user passed, or the defaults), with a
    :class:`DeprecationWarning` naming the group to pass instead. A flat name of
    a group the caller does not take, or of none, is a TypeError.
    """
    out = {}
    for keyword, given in groups.items():
        cls = GROUPS[keyword]
        if given is not None and not isinstance(given, cls):
            raise TypeError(
                f"{keyword} must be a comcore.{cls.__name__} or None, got {type(given).__name__}"
            )
        out[keyword] = cls() if given is None else given
    if not flat:
        return out
    refused = sorted(
        k for k in flat if (GROUPS.get(k) or _GROUP_OF.get(k)) and _group_of(k) not in groups
    )
    if refused:
        raise TypeError(f"{caller} chooses no pushes: option(s) {refused} do not apply")
    parsed = option_groups(**flat)
    hints = []
    for keyword, group in parsed.items():
        mine = {k: v for k, v in flat.items() if _GROUP_OF[k] == keyword}
        out[keyword] = dataclasses.replace(out[keyword], **mine)
        args = ", ".join(f"{k}={v!r}" for k, v in mine.items())
        hints.append(f"{keyword}=comcore.{type(group).__name__}({args})")
    warnings.warn(
        f"{caller}: flat options {sorted(flat)} are deprecated and will be removed: "
        f"pass {', '.join(hints)}",
        DeprecationWarning,
        stacklevel=stacklevel,
    )
    return out

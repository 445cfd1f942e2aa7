"""The option groups: built from flat names, checked where an entry point takes them.

The entry points take their options in groups
(``estimate_active(mask, push, stop=comcore.StopRule(max_pushes=3))``).
:func:`option_groups` builds the groups from flat names, for configuration files
and command lines (``comcore bench`` labels); :func:`check_groups` gives an entry
point the groups it was passed (the defaults for None); :func:`names_the_group`
turns a flat option passed to an entry point (``max_pushes=3``, as the paper
names it) into a TypeError that says which group to pass instead.
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import inspect
from typing import Any

from ._likelihood import Likelihood
from ._options import PushChoice, StopRule

__all__ = ["GROUPS", "check_groups", "names_the_group", "option_groups"]

#: The groups and the keyword each is passed as.
GROUPS = {"likelihood": Likelihood, "stop": StopRule, "choice": PushChoice}
#: Which group each flat option name belongs to.
_GROUP_OF = {
    f.name: keyword for keyword, cls in GROUPS.items() for f in dataclasses.fields(cls)
}


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


def check_groups(**groups) -> dict[str, Any]:
    """The option groups an entry point runs with: each as passed, or its defaults for None.

    ``groups`` maps each keyword the entry point takes (``likelihood``, ``stop``,
    ``choice``) to what the user passed.

    Raises
    ------
    TypeError
        On a value that is neither its group nor None.

    Examples
    --------
    >>> check_groups(stop=None)["stop"].max_pushes
    5
    >>> check_groups(stop={"max_pushes": 3})
    Traceback (most recent call last):
    ...
    TypeError: stop must be a comcore.StopRule or None, got dict
    """
    out = {}
    for keyword, given in groups.items():
        cls = GROUPS[keyword]
        if given is not None and not isinstance(given, cls):
            raise TypeError(
                f"{keyword} must be a comcore.{cls.__name__} or None, got {type(given).__name__}"
            )
        out[keyword] = cls() if given is None else given
    return out


def names_the_group(entry):
    """Make a flat option passed to ``entry`` a TypeError naming the group to pass instead.

    ``entry`` (a function, or a class's ``__init__``) keeps its signature and takes
    no ``**kwargs``: only a call with a keyword it does not take is checked, and
    refused with a message that helps (the group and the call to make, or why the
    group does not apply); any other unknown keyword is refused as Python refuses it,
    with the closest option named.
    """
    takes = set(inspect.signature(entry).parameters)
    name = entry.__qualname__.removesuffix(".__init__")

    @functools.wraps(entry)
    def checked(*args, **kwargs):
        unknown = sorted(set(kwargs) - takes)
        if unknown:
            raise TypeError(_refusal(name, unknown, kwargs, takes))
        return entry(*args, **kwargs)

    return checked


#: Entry points that take a group for some of its fields only, the field each reads, and why
#: the others do not apply (:func:`check_reads_only` refuses them in a group, and
#: :func:`names_the_group` as flat keywords).
READS_ONLY = {
    "estimate_posterior": ({"stop": "target_radius"}, "chooses no pushes"),
    "GoalSession": (
        {"stop": "max_pushes", "choice": "travel"},
        "plans its own pushes and stops at the goal",
    ),
}


def _refusal(name: str, unknown: list[str], kwargs: dict, takes: set[str]) -> str:
    """What :func:`names_the_group` says of the keywords ``unknown`` passed to ``name``."""
    grouped = [k for k in unknown if k in GROUPS or k in _GROUP_OF]
    only, why = READS_ONLY.get(name, ({}, "chooses no pushes"))
    refused = [
        k for k in grouped
        if (g := k if k in GROUPS else _GROUP_OF[k]) not in takes or only.get(g, k) != k
    ]  # fmt: skip
    if refused:
        return f"{name} {why}: option(s) {refused} do not apply"
    others = [k for k in unknown if k not in grouped]
    parts = [_in_groups(name, grouped, kwargs)] if grouped else []
    if others:
        parts.append(_unexpected(name, others, kwargs, takes))
    return "; and ".join(parts)


def _in_groups(name: str, grouped: list[str], kwargs: dict) -> str:
    """The group each flat option belongs in, as the call to make."""
    hints = []
    for keyword, cls in GROUPS.items():
        mine = ", ".join(f"{k}={kwargs[k]!r}" for k in grouped if _GROUP_OF.get(k) == keyword)
        if mine:
            hints.append(f"{keyword}=comcore.{cls.__name__}({mine})")
    flat = ", ".join(f"{k}={kwargs[k]!r}" for k in grouped)
    return f"{name}() takes its options in groups: pass {', '.join(hints)} instead of {flat}"


def _unexpected(name: str, others: list[str], kwargs: dict, takes: set[str]) -> str:
    """Keywords of no group: option_groups' message for a removed one, else the closest names."""
    try:
        option_groups(**{k: kwargs[k] for k in others})  # its messages for removed options
    except TypeError as e:
        if "unknown option" not in str(e):
            return str(e)
    known = sorted(takes | set(_GROUP_OF))
    guesses = ""
    for k in others:
        close = difflib.get_close_matches(k, known, n=1)
        if close:
            guess = close[0]
            if guess not in takes:
                keyword = _GROUP_OF[guess]
                guess = f"{keyword}=comcore.{GROUPS[keyword].__name__}({guess}=...)"
            guesses += f"; {k}: did you mean {guess}?"
    return f"{name}() got unexpected keyword argument(s) {others}{guesses}"


def check_reads_only(who: str, groups: dict) -> None:
    """Refuse a group of ``groups`` whose fields but the one ``who`` reads changed.

    ``who`` is an entry point of :data:`READS_ONLY` (``estimate_posterior``,
    ``GoalSession``), ``groups`` what :func:`check_groups` returned for it: a
    changed field it does not read would be silently ignored.

    >>> from comcore import StopRule
    >>> check_reads_only("estimate_posterior", {"stop": StopRule(target_radius=0.01)})
    >>> check_reads_only("estimate_posterior", {"stop": StopRule(max_pushes=3)})
    Traceback (most recent call last):
    ...
    ValueError: estimate_posterior reads only StopRule.target_radius (it chooses no pushes): ['max_pushes'] do not apply
    """  # noqa: E501
    reads, why = READS_ONLY[who]
    for keyword, read in reads.items():
        group = groups[keyword]
        default = type(group)()
        other = [
            f.name for f in dataclasses.fields(group)
            if f.name != read and getattr(group, f.name) != getattr(default, f.name)
        ]  # fmt: skip
        if other:
            raise ValueError(
                f"{who} reads only {type(group).__name__}.{read} (it {why}): {other} do not apply"
            )

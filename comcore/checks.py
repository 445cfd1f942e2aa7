"""The validators every public function calls first: one ``check_*`` per kind of input.

For authors of predictors, simulators and robot adapters who take the same inputs
as comcore and want the same errors: each returns the cleaned value (a float, a
read-only array, a :class:`~comcore.Mask`) or raises a :class:`ValueError` or
:class:`TypeError` that names the argument, says what was expected and what
arrived, and guesses the likely mistake where it can; :func:`readonly` makes
the read-only copy a frozen record holds. Imports only the base
modules of :mod:`comcore` (no subpackage).

Examples
--------
>>> from comcore import checks
>>> checks.check_positive(0.002, "pusher_radius")
0.002
>>> checks.check_actions([(0, 0, 10, 0)]).shape
(1, 4)
"""

from __future__ import annotations

from ._checks import check_point, check_points
from ._types import readonly
from ._validation import (
    check_actions,
    check_mask,
    check_motions,
    check_mu,
    check_one_object,
    check_positive,
    check_priors,
    check_probability,
    check_rng,
)
from .conventions import check_plausible

__all__ = [
    "check_actions",
    "check_mask",
    "check_motions",
    "check_mu",
    "check_one_object",
    "check_plausible",
    "check_point",
    "check_points",
    "check_positive",
    "check_priors",
    "check_probability",
    "check_rng",
    "readonly",
]

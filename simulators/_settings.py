"""Numerical settings of the simulators' engines (defaults: docs/results/simulators.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ENGINES", "EngineSettings"]

#: The engines: the batched quasi-static integrator and the pymunk rigid-body engine.
ENGINES = ("quasistatic", "pymunk")
#: Most ``projections``, ``iterations`` and ``settle_steps``: each multiplies the work of
#: every integration step (the defaults are 2, 10 and 4); a million would run for hours.
MAX_STEP_COUNT = 1000


@dataclass(frozen=True)
class EngineSettings:
    """How a :class:`~simulators.PushSimulator` integrates a push.

    Attributes
    ----------
    engine : {"quasistatic", "pymunk"}
        ``"quasistatic"`` (default) solves the quasi-static pusher-slider problem
        exactly on the limit surface of the support, all pushes of a batch at
        once in numpy. ``"pymunk"`` runs the rigid-body engine with one friction
        joint per support point; it is slower and, at affordable solver
        iterations, less accurate (see docs/results/simulators.md).
    step_m : float
        Pusher travel per integration step, metres.
    projections : int
        Quasi-static engine: contact resolutions per step (2 lets a pusher
        touching two edges of a notch push on both).
    iterations : int
        pymunk engine: solver iterations per step.
    quasi_static_ratio : float
        pymunk engine: ``mu_floor g dt^2 / step``, how many times over one step
        floor friction could stop the body (larger is more quasi-static but the
        solver converges more slowly).
    settle_steps : int
        pymunk engine: steps run after the pusher stops.

    Examples
    --------
    >>> EngineSettings(engine="pymunk", iterations=20).engine
    'pymunk'
    >>> EngineSettings(engine="box2d")
    Traceback (most recent call last):
    ...
    ValueError: engine must be one of ('quasistatic', 'pymunk'), got 'box2d'
    """

    engine: str = "quasistatic"
    step_m: float = 0.001
    projections: int = 2
    iterations: int = 10
    quasi_static_ratio: float = 3.0
    settle_steps: int = 4

    def __post_init__(self):
        if not isinstance(self.engine, str) or self.engine not in ENGINES:
            raise ValueError(f"engine must be one of {ENGINES}, got {self.engine!r}")
        for name in ("step_m", "quasi_static_ratio"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer,
                                                                 np.floating)):
                raise TypeError(f"{name} must be a number, got {type(value).__name__}")
            object.__setattr__(self, name, float(value))
        if not 0 < self.step_m <= 0.01:
            raise ValueError(f"step_m must be in (0, 0.01] metres, got {self.step_m}")
        if not (self.quasi_static_ratio > 0 and math.isfinite(self.quasi_static_ratio)):
            raise ValueError(f"quasi_static_ratio must be > 0, got {self.quasi_static_ratio}")
        for name, low in (("projections", 1), ("iterations", 1), ("settle_steps", 0)):
            value = getattr(self, name)
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
                raise TypeError(f"{name} must be an integer, got {type(value).__name__}")
            if not low <= value <= MAX_STEP_COUNT:
                raise ValueError(
                    f"{name} must be an integer from {low} to {MAX_STEP_COUNT} "
                    f"(MAX_STEP_COUNT), got {value}"
                )
            object.__setattr__(self, name, int(value))

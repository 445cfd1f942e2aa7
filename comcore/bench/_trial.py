"""One benchmark trial: a random object instance, candidate pushes, every estimator."""

from __future__ import annotations

import zlib
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

import comcore

from . import _builtins  # noqa: F401  (registers the built-in estimators and predictors)
from ._realism import CONDITIONS, ConditionWorld
from ._registry import PREDICTORS, TrialContext, parse_estimator

__all__ = [
    "DEFAULT_CANDIDATES",
    "DEFAULT_CONE",
    "DEFAULT_ESTIMATORS",
    "ROW_FIELDS",
    "TrialOutcome",
    "TrialSpec",
    "run_trial",
    "trial_rng",
]

#: Candidate pushes per trial (see docs/how-to/benchmark.md for why 30).
DEFAULT_CANDIDATES = 30
#: Half-angle (radians) of the candidate push directions about the inward normal.
DEFAULT_CONE = 0.3
#: Estimators run by default: the paper's two algorithms, the Fig. 7 ablation, the baseline.
DEFAULT_ESTIMATORS = ("alg1", "alg2", "alg2-rotation", "centroid")
#: Draws of a random simulator before a trial gives up.
SIMULATOR_ATTEMPTS = 4
#: Columns of a result row, in order.
ROW_FIELDS = (
    "object", "friction", "trial", "estimator", "predictor", "status", "error_cm", "error_px",
    "pushes_used", "prior_pushes", "total_pushes", "true_x_px", "true_y_px", "est_x_px",
    "est_y_px", "mu", "area_cm2", "candidates", "cone", "seed", "message",
    "condition", "covered", "credible_radius_cm", "push_failures",
)  # fmt: skip


def _stable_id(text: str) -> int:
    return zlib.crc32(text.encode("utf-8"))


def trial_rng(seed: int, object: str, friction: str, trial: int, stream: str):
    """The generator of one random stream of one trial.

    Seeded from ``(seed, object, friction, trial, stream)`` through
    :class:`numpy.random.SeedSequence` (names hashed with CRC-32), so a trial's
    draws depend neither on the other trials nor on the order they run in.

    Examples
    --------
    >>> a = trial_rng(0, "Obj1", "low", 3, "candidates").random()
    >>> b = trial_rng(0, "Obj1", "low", 3, "candidates").random()
    >>> a == b, a == trial_rng(0, "Obj1", "low", 4, "candidates").random()
    (True, False)
    """
    entropy = [int(seed), _stable_id(object), _stable_id(friction), int(trial), _stable_id(stream)]
    return np.random.default_rng(np.random.SeedSequence(entropy))


@dataclass(frozen=True)
class TrialSpec:
    """What one trial runs; it fully determines the trial's result rows.

    Attributes
    ----------
    object : str
        Benchmark object name (``simulators.load_object``).
    friction : str
        Friction class, ``"low"`` or ``"high"``.
    trial : int
        Index of the trial (>= 0).
    seed : int
        Seed of the whole benchmark (>= 0).
    predictor : str
        Name in :data:`comcore.bench.PREDICTORS`.
    estimators : tuple of str
        Estimator labels (:func:`comcore.bench.parse_estimator`).
    candidates : int
        Number of random candidate pushes.
    cone : float
        Half-angle in radians of their directions about the inward normal.
    condition : comcore.bench.Condition or None
        The realism condition the trial runs under (``None``: the plain benchmark,
        the same as the ``exact`` condition).
    """

    object: str
    friction: str
    trial: int
    seed: int = 0
    predictor: str = "oracle"
    estimators: tuple[str, ...] = DEFAULT_ESTIMATORS
    candidates: int = DEFAULT_CANDIDATES
    cone: float = DEFAULT_CONE
    condition: Any = None

    def rng(self, stream: str) -> np.random.Generator:
        """The generator of one of this trial's random streams."""
        return trial_rng(self.seed, self.object, self.friction, self.trial, stream)

    def simulator(self, on_refusal=None):
        """The trial's random object: ``simulators.accepted_random_simulator``'s draw.

        Drawn from the stream ``"simulator"``; a draw the simulator refuses is
        redrawn from ``"simulator#1"``, ``"simulator#2"``, ... (at most
        :data:`SIMULATOR_ATTEMPTS` draws), and ``on_refusal(attempt, error)`` is
        told of each refusal.
        """
        import simulators

        return simulators.accepted_random_simulator(
            self.object,
            self.friction,
            rng=lambda attempt: self.rng("simulator" if attempt == 0 else f"simulator#{attempt}"),
            attempts=SIMULATOR_ATTEMPTS,
            on_refusal=on_refusal,
        )


@dataclass(frozen=True)
class TrialOutcome:
    """A trial's rows with the objects behind them (for figures)."""

    rows: list[dict]
    context: TrialContext
    estimates: dict[str, comcore.Estimate] = field(default_factory=dict)


class _RobotFactory:
    """``ctx.robot(**options)``: the trial's object as a robot, its pushes counted."""

    def __init__(self, simulator, condition, rng):
        self.simulator, self.condition, self.rng = simulator, condition, rng
        self.robots: list = []

    def __call__(self, **options):
        condition = self.condition if self.condition is not None else CONDITIONS["exact"]
        robot = condition.robot(self.simulator, self.rng, **options)
        self.robots.append(robot)
        return robot

    @property
    def count(self) -> int:
        return sum(r.pushes for r in self.robots)


class _CountingPush:
    """``push(action) -> Motion`` on the simulator from its initial pose, counted."""

    def __init__(self, simulator):
        self.simulator = simulator
        self.count = 0

    def __call__(self, action) -> comcore.Motion:
        self.count += 1
        return self.simulator.push(action).motion


def _row(spec: TrialSpec, ctx: TrialContext, label: str, predictor: str, **values) -> dict:
    sim, mask = ctx.simulator, ctx.mask
    est = values.pop("estimate")
    robot = values.pop("robot", None)
    truth, resolution = sim.com_px, mask.resolution
    if robot is not None:  # scored in the frame of the camera the estimator saw
        truth, resolution = robot.true_com_px, robot.resolution
    error_px = est.error_px(truth)
    radius = None if est.posterior is None else est.posterior.credible_radius_px
    condition = spec.condition.name if spec.condition is not None else "exact"
    row: dict[str, Any] = {
        "object": spec.object,
        "friction": spec.friction,
        "trial": spec.trial,
        "estimator": label,
        "predictor": predictor,
        "status": est.status,
        "error_cm": error_px * resolution * 100.0,
        "error_px": error_px,
        "true_x_px": float(truth[0]),
        "true_y_px": float(truth[1]),
        "est_x_px": est.com[0],
        "est_y_px": est.com[1],
        "mu": float(sim.mu_contact),
        "area_cm2": mask.area_m2 * 1e4,
        "candidates": spec.candidates,
        "cone": spec.cone,
        "seed": spec.seed,
        "message": "",
        "condition": condition,
        "covered": est.region_holds(truth),
        "credible_radius_cm": None if radius is None else float(radius) * resolution * 100.0,
        "push_failures": sum(p.outcome == "failed" for p in est.pushes),
    }
    row.update(values)
    row["total_pushes"] = row["pushes_used"] + row["prior_pushes"]
    return {key: row[key] for key in ROW_FIELDS}


def _predictions(spec: TrialSpec, ctx: TrialContext):
    """The context with candidates, priors and motions, and a note on redrawn pushes."""
    import simulators

    predictor, sim, mask = PREDICTORS[spec.predictor], ctx.simulator, ctx.mask
    note, priors = "", ()
    accepted = simulators.sample_accepted_pushes
    if predictor.prior_pushes:
        acts, mots, rejected = accepted(
            sim, predictor.prior_pushes, cone=spec.cone, rng=spec.rng("prior")
        )
        priors = tuple((comcore.Action(*a), comcore.Motion(*m)) for a, m in zip(acts, mots))
        note += f"{rejected} prior push(es) redrawn; " if rejected else ""
    rng = spec.rng("cand")
    if predictor.pushes_object and spec.condition is not None and not spec.condition.plain:
        # the oracle under a condition: the condition's observations
        cands, motions, rejected = accepted(sim, spec.candidates, cone=spec.cone, rng=rng)
        note += f"{rejected} candidate push(es) redrawn; " if rejected else ""
        return replace(ctx, candidates=cands, motions=motions, priors=priors), note
    model = predictor.make(replace(ctx, priors=priors))
    if predictor.pushes_object:  # predicting is pushing: redraw what the simulator refuses
        cands, motions, rejected = accepted(
            sim,
            spec.candidates,
            cone=spec.cone,
            rng=rng,
            respond=lambda a: comcore.motion.predict_motions(model, mask, a, priors),
        )
        note += f"{rejected} candidate push(es) redrawn; " if rejected else ""
    else:
        cands = comcore.sample_pushes(mask, spec.candidates, cone=spec.cone, rng=rng)
        motions = comcore.motion.predict_motions(model, mask, cands, priors)
    return replace(ctx, candidates=cands, motions=motions, priors=priors), note


def run_trial(spec: TrialSpec, *, keep: bool = False):
    """Run one trial: every estimator of ``spec`` on one random object instance.

    The object's mass distribution and ``mu_contact`` come from
    ``simulators.random_simulator`` (friction class ``spec.friction``), the
    candidates from :func:`comcore.sample_pushes`, their motions from the
    predictor (conditioned on prior pushes run in the simulator for learned
    predictors). Every failure is recorded, never raised, and said in the
    rows' ``message``: a failed ``random_simulator`` draw is redrawn from the
    streams ``"simulator#1"``, ...; a push the simulator refuses (a prior, or
    a candidate of the oracle) is replaced by a fresh draw; if the predictor
    fails, the estimators that need its motions get ``status`` ``"error"``;
    an estimator that raises gets ``status`` ``"error"``. Errors come with the
    centroid as the estimate.

    Parameters
    ----------
    spec : TrialSpec
    keep : bool, optional
        Also return the context and the estimates (a :class:`TrialOutcome`).

    Returns
    -------
    list of dict or TrialOutcome
        One row per estimator, with the keys :data:`ROW_FIELDS`.
    """
    parsed = [(label, *parse_estimator(label)) for label in spec.estimators]
    refused: list[str] = []
    sim = spec.simulator(
        lambda attempt, e: refused.append(f"simulator draw {attempt} failed ({e}); ")
    )
    note = "".join(refused)
    condition, world = spec.condition, None
    if condition is not None and not condition.plain:
        world = ConditionWorld(condition, sim, spec.rng("condition"))
        sim = world
    robot_sim = world.base if world is not None else sim
    mask = sim.mask
    ctx = TrialContext(spec.object, spec.friction, spec.trial, sim, mask, np.empty((0, 4)), None)
    failure = ""
    if any(est.uses_motions for _, est, _ in parsed):
        try:
            ctx, more = _predictions(spec, ctx)
            note += more
        except Exception as e:  # one bad trial must not end a long benchmark
            failure = f"predictor {spec.predictor!r} failed: {type(e).__name__}: {e}"
    if not len(ctx.candidates):
        cands = comcore.sample_pushes(mask, spec.candidates, cone=spec.cone, rng=spec.rng("cand"))
        ctx = replace(ctx, candidates=cands)
    prior_count = len(ctx.priors)
    rows, estimates = [], {}
    for label, est_spec, options in parsed:
        own = sim if world is None else world.with_rng(spec.rng("condition:" + label))
        counter = _CountingPush(own)
        robots = _RobotFactory(robot_sim, condition, spec.rng("robot:" + label))
        run_ctx = replace(
            ctx,
            rng=spec.rng("estimator:" + label),
            push=counter,
            robot=robots,
            condition=condition,
        )
        message = note
        try:
            if est_spec.uses_motions and failure:
                raise RuntimeError(failure)
            est = est_spec.run(run_ctx, **options)
        except Exception as e:  # one bad trial must not end a long benchmark
            message = f"{note}{type(e).__name__}: {e}"
            seen = robots.robots[-1].simulator.mask if robots.robots else mask  # its frame
            est = comcore.Estimate(
                seen.centroid, seen.centroid_m, seen.data, status=comcore.Status.ERROR
            )
        if est_spec.uses_motions:
            used, prior = len(est.used), prior_count
        else:
            used, prior = counter.count + robots.count, 0
        estimates[label] = est
        robot = robots.robots[-1] if robots.robots else None
        values = {"pushes_used": used, "prior_pushes": prior, "message": message, "robot": robot}
        rows.append(_row(spec, ctx, label, spec.predictor, estimate=est, **values))
        for used in robots.robots:  # a MuJoCo robot holds a GL context: free it now
            getattr(used, "close", lambda: None)()
    return TrialOutcome(rows, ctx, estimates) if keep else rows

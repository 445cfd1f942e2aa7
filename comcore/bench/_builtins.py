"""The estimators and predictors the benchmark knows out of the box."""

from __future__ import annotations

import dataclasses

import numpy as np

import comcore

from ._registry import (
    PREDICTORS,
    PredictorSpec,
    TrialContext,
    missing,
    option_groups,
    register_estimator,
    requirements,
)

__all__: list[str] = []

_SIM = missing("simulators", "PushSimulator", "pip install comcore[sim]")
_ORACLE = requirements(_SIM, missing("predictors", "OraclePredictor", "pip install comcore[sim]"))
_ELLIPSOID = missing("predictors", "EllipsoidPredictor")
_ACTIVE = missing("comcore", "estimate_active")
_SESSION = requirements(
    missing("comcore", "ActiveSession"),
    missing("comcore", "measure_motion"),
    missing("simulators", "SimulatedRobot", "pip install comcore[sim]"),
)
#: Pushes the robot may fail to execute in one run before ``active-robot`` gives up.
MAX_PUSH_FAILURES = 3


def _alg1(ctx: TrialContext, **options) -> comcore.Estimate:
    return comcore.estimate_heatmap(ctx.mask, ctx.candidates, ctx.motions, **options)


def _alg2(ctx: TrialContext, **options) -> comcore.Estimate:
    return comcore.estimate_progressive(ctx.mask, ctx.candidates, ctx.motions, **options)


def _alg2_rotation(ctx: TrialContext, **options) -> comcore.Estimate:
    options = {"selection": "rotation", **options}
    return comcore.estimate_progressive(ctx.mask, ctx.candidates, ctx.motions, **options)


def _centroid(ctx: TrialContext) -> comcore.Estimate:
    mask = ctx.mask
    return comcore.Estimate(  # a baseline that uses no push: nothing is checked
        com=mask.centroid,
        com_m=mask.centroid_m,
        region=mask.data,
        status=comcore.Status.UNCHECKED,
    )


#: The ``model`` option of the active estimators.
MODELS = ("default", "limit-surface", "ellipsoid", None, "none")


def _hypothesis_model(ctx: TrialContext, model):
    if model is None or model == "none":
        return None
    if model == "ellipsoid":
        from predictors import EllipsoidPredictor

        return EllipsoidPredictor(pusher_radius=ctx.simulator.pusher_radius)
    if model == "limit-surface":
        return comcore.LimitSurfaceModel(pusher_radius=ctx.simulator.pusher_radius)
    raise ValueError(
        f"model must be 'default', 'limit-surface', 'ellipsoid' or None, got {model!r}"
    )


def _model_options(ctx: TrialContext, model) -> dict:
    """``"default"``: as a user runs it, comcore's own model and the robot's pusher radius."""
    if model == "default":
        return {"pusher_radius": ctx.simulator.pusher_radius}
    return {"model": _hypothesis_model(ctx, model)}


def _active(ctx: TrialContext, model="default", candidates="own", **options):
    """Run :func:`comcore.estimate_active` on the trial's object, with its own defaults.

    ``candidates``: ``"own"`` (default: the estimator draws its pushes, 200 along the
    inward normals, from the trial's estimator stream) or ``"trial"`` (the trial's random
    candidates, the set Alg. 1 and Alg. 2 choose from). Choosing its pushes is part of what
    the active estimator is for; ``"trial"`` measures it on Alg. 2's terms.
    """
    if candidates not in ("trial", "own"):
        raise ValueError(f"candidates must be 'trial' or 'own', got {candidates!r}")
    return comcore.estimate_active(  # type: ignore[attr-defined]
        ctx.mask,
        ctx.push,
        ctx.candidates if candidates == "trial" else None,
        **_model_options(ctx, model),
        rng=ctx.rng,
        **option_groups(**options),
    )


def _active_vt(ctx: TrialContext, **options):
    return _active(ctx, **{"model": None, **options})


#: How ``active-robot`` shows the session what a push did.
OBSERVATIONS = ("mask", "consecutive", "video", "motion")


def _tracked_motion(before, frames) -> comcore.Motion:
    """The motion from ``before`` to the last of ``frames``, chained frame to frame.

    In the camera frame about ``before``'s area centroid: each step's motion
    (:func:`comcore.measure_motion`) moves the tracked point about the centroid of
    the frame it starts from (:func:`comcore.apply_motion`).
    """
    start = np.array(before.centroid, float)
    point, theta, prev = start.copy(), 0.0, before
    for frame in frames:
        m = comcore.measure_motion(prev, frame).motion  # type: ignore[attr-defined]
        point = comcore.apply_motion(point, m.theta, (m.tx, m.ty), prev.centroid)
        theta, prev = theta + m.theta, frame
    return comcore.Motion(theta, *(np.asarray(point, float).reshape(2) - start))


def _active_robot(
    ctx: TrialContext,
    *,
    model="default",
    observe=None,
    motion_noise=None,
    pusher_error=None,
    mask_noise=None,
    camera_margin=None,
    frames=8,
    executed=False,
    frame_rate=None,
    **options,
):
    """:class:`comcore.ActiveSession` against ``simulators.SimulatedRobot``, never reset.

    Each push starts from the pose the last one left. ``observe="mask"`` (default):
    the session gets the camera's mask after every push and measures the pose
    itself (against the first mask); ``"consecutive"``: the motion of each push is
    measured between the camera's masks before and after it
    (:func:`comcore.measure_motion`) and handed in as ``motion=``; ``"video"``: the
    same, chained over ``frames`` camera masks taken during the push (a tracker
    following the object, which a rotational symmetry cannot fool); ``"motion"``: it
    gets the robot's exact motion plus ``motion_noise`` ``(radians, metres)`` of
    tracking noise (the default under the ``motion-noise`` condition).
    ``pusher_error`` (metres), ``mask_noise`` (flip probability) and
    ``camera_margin`` (metres) override the trial condition's.
    A push the robot refuses is reported with ``observe(failed=True)``;
    its :class:`comcore.PushRecord` (outcome ``"failed"``) counts it.
    ``executed=True`` also tells the session the pusher's real path
    (``observe(..., executed=push.executed)``: a pusher tracked in the camera), so
    the pusher's error is measured, not guessed. ``frame_rate`` (Hz): the camera's
    frames during each push, at that rate with the pusher at the robot's speed,
    go to the session too (``observe(mask, frames=push.path)``; with ``observe="mask"``).
    """
    condition = ctx.condition
    if observe is None:
        noisy = condition is not None and condition.motion_noise is not None
        observe = "motion" if noisy else "mask"
    if observe not in OBSERVATIONS:
        raise ValueError(f"observe must be one of {OBSERVATIONS}, got {observe!r}")
    if motion_noise is None and condition is not None:
        motion_noise = condition.motion_noise
    overrides = {"pusher_error": pusher_error, "mask_noise": mask_noise}
    overrides["camera_margin"] = camera_margin
    robot = ctx.robot(**{k: v for k, v in overrides.items() if v is not None})
    noise_rng = np.random.default_rng(ctx.rng.integers(2**63))
    seen = first = robot.camera_mask()
    session = comcore.ActiveSession(  # type: ignore[attr-defined]
        first, **_model_options(ctx, model), rng=ctx.rng, **option_groups(**options)
    )
    failures = 0
    while not session.done:
        action = session.next_push()
        try:
            if frame_rate is not None:
                push = robot.execute(action, frame_rate=float(frame_rate))
            else:
                push = robot.execute(action, frames=frames if observe == "video" else 0)
        except ValueError:
            failures += 1
            session.observe(failed=True)
            if failures >= MAX_PUSH_FAILURES:
                break
            continue
        path = {"executed": push.executed} if executed else {}
        if frame_rate is not None:
            path["frames"] = push.path
        if observe == "mask":
            session.observe(robot.camera_mask(), **path)
            continue
        if observe in ("consecutive", "video"):
            shots = push.frames or (robot.camera_mask(),)
            session.observe(motion=_tracked_motion(seen, shots), **path)
            seen = shots[-1]
            continue
        motion = np.asarray(push.motion, float)
        if motion_noise is not None:
            theta, shift = motion_noise
            scale = np.array([theta, shift / robot.resolution, shift / robot.resolution])
            motion = motion + noise_rng.normal(0.0, 1.0, 3) * scale
        session.observe(motion=comcore.Motion(*motion), **path)
    est = session.estimate()
    extras = {
        **est.extras,
        "robot_pose": tuple(robot.pose),
        "first_mask": first,  # the frame of the estimate's pushes (a replay scores them on it)
    }
    return dataclasses.replace(est, extras=extras)


register_estimator("alg1", _alg1, description="Alg. 1: calmest region of the rotation heat map")
register_estimator(
    "alg2", _alg2, description="Alg. 2: progressive Voting-Theorem cuts, equality-score order"
)
register_estimator(
    "alg2-rotation",
    _alg2_rotation,
    description="Alg. 2 taking pushes in ascending |theta| (the paper's Fig. 7 ablation)",
)
register_estimator(
    "centroid",
    _centroid,
    description="baseline: the mask's area centroid (no push)",
    uses_motions=False,
    resets=False,
)
register_estimator(
    "active",
    _active,
    description="the active estimator (comcore.estimate_active): chooses and executes its own "
    "pushes on the object, reset before each, and stops when its 90 % region is small; its "
    "defaults (limit-surface model, at most 5 pushes). model='default'|'limit-surface'|"
    "'ellipsoid'|None, candidates='own'|'trial'",
    uses_motions=False,
    requires=requirements(_ACTIVE, _ELLIPSOID),
)
register_estimator(
    "active-robot",
    _active_robot,
    description="comcore.ActiveSession on simulators.SimulatedRobot: never reset, poses "
    "measured from the camera's masks. observe='mask'|'consecutive'|'video'|'motion'",
    uses_motions=False,
    requires=requirements(_SESSION, _ELLIPSOID),
    resets=False,
)
register_estimator(
    "active-vt",
    _active_vt,
    description="comcore.estimate_active with the Voting Theorem alone (model=None)",
    uses_motions=False,
    requires=_ACTIVE,
)


def _oracle(ctx: TrialContext):
    from predictors import OraclePredictor

    return OraclePredictor(ctx.simulator)


def _ellipsoid(ctx: TrialContext):
    from predictors import EllipsoidPredictor

    return EllipsoidPredictor(pusher_radius=ctx.simulator.pusher_radius)


def _anp(ctx: TrialContext):
    from predictors import AnpPredictor

    return AnpPredictor()


PREDICTORS["oracle"] = PredictorSpec("oracle", _oracle, 0, _ORACLE, pushes_object=True)
PREDICTORS["ellipsoid"] = PredictorSpec("ellipsoid", _ellipsoid, 12, _ELLIPSOID)
PREDICTORS["anp"] = PredictorSpec(
    "anp", _anp, 12, missing("predictors", "AnpPredictor", "pip install comcore[anp]")
)

"""Realism conditions: the same benchmark trials with a real robot's errors (``--conditions``).

A condition changes how the trial's object answers a push, never which object
it is: every condition runs the same trials (same seeds, same mass
distributions and friction), and the estimators see the object only through
the condition. The built-in conditions (:data:`CONDITIONS`, docs/robot.md):

========================  =====================================================
``exact``                 today's benchmark: every push from the initial pose,
                          exact motions from the default (quasi-static) engine
``pymunk``                the pymunk rigid-body engine plays the object
``pusher-error``          the pusher misses its path by 3 mm (std) across the push
``motion-noise``          tracking noise on every motion handed in: 0.5 deg on
                          the rotation, 0.5 mm on each displacement component (std)
``mask-noise``            the camera's masks have noisy outlines (each outline
                          pixel flipped with probability 0.5) and every motion is
                          measured from two masks (:func:`comcore.measure_motion`)
``resolution-0.1``        the camera at 0.1 cm per pixel (1 mm) instead of 2.5 mm
``no-reset``              the object is never put back: only estimators that push
                          from where the last push left it (``active-robot``) run
========================  =====================================================

Options change a condition's numbers: ``"pusher-error(pusher_error=0.001)"``,
``"motion-noise(motion_noise=(0.035, 0.002))"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

import comcore

from ._registry import EstimatorSpec, parse_call, parse_estimator, split_estimators
from ._runner import BenchConfig, BenchResult, run_benchmark
from ._trial import TrialSpec

__all__ = [
    "CONDITIONS",
    "Condition",
    "ConditionConfig",
    "ConditionWorld",
    "conditions_table",
    "friction_table",
    "parse_condition",
    "run_conditions",
    "run_conditions_command",
]

#: Outline-pixel flip probability of the ``mask-noise`` condition.
MASK_NOISE = 0.5
#: Pusher position error (std across the push, metres) of ``pusher-error``.
PUSHER_ERROR_M = 0.003
#: Tracking noise (std): rotation in radians, each displacement component in metres.
MOTION_NOISE = (math.radians(0.5), 0.0005)


@dataclass(frozen=True)
class Condition:
    """How the trial's object answers pushes (see the module docstring).

    Attributes
    ----------
    name : str
        The label it is reported under.
    description : str
    engine : str or None
        The simulator engine playing the object (``None``: the trial's, quasi-static).
    resolution : float or None
        Metres per camera pixel (``None``: the benchmark's 2.5 mm).
    pusher_error : float
        Std (metres) of the pusher's position across each push.
    motion_noise : (float, float) or None
        Std of the tracking noise added to every motion: rotation (radians) and
        each displacement component (metres).
    mask_noise : float
        Flip probability of each outline pixel of a camera mask.
    measured : bool
        Motions are measured from the camera's masks (:func:`comcore.measure_motion`),
        not taken from the simulator; the camera frame is then the robot's
        (``simulators.SimulatedRobot``: wide enough to keep a pushed object in view).
    resets : bool
        ``False``: the object is never put back; estimators that need it are not run.
    """

    name: str
    description: str = ""
    engine: str | None = None
    resolution: float | None = None
    pusher_error: float = 0.0
    motion_noise: tuple[float, float] | None = None
    mask_noise: float = 0.0
    measured: bool = False
    resets: bool = True

    def __post_init__(self):
        from comcore._validation import check_positive, check_probability

        if self.engine is not None:
            import simulators

            if self.engine not in simulators.ENGINES:
                raise ValueError(
                    f"condition {self.name!r}: engine must be one of {simulators.ENGINES}, "
                    f"got {self.engine!r}"
                )
        if self.resolution is not None:
            check_positive(self.resolution, f"condition {self.name!r}: resolution")
        check_positive(self.pusher_error, f"condition {self.name!r}: pusher_error", allow_zero=True)
        check_probability(self.mask_noise, f"condition {self.name!r}: mask_noise", open_high=True)
        if self.motion_noise is not None:
            try:
                theta, shift = (float(v) for v in self.motion_noise)
            except (TypeError, ValueError) as e:
                raise TypeError(
                    f"condition {self.name!r}: motion_noise must be (radians, metres), "
                    f"got {self.motion_noise!r}"
                ) from e
            check_positive(theta, f"condition {self.name!r}: motion_noise[0]", allow_zero=True)
            check_positive(shift, f"condition {self.name!r}: motion_noise[1]", allow_zero=True)
            object.__setattr__(self, "motion_noise", (theta, shift))

    @property
    def plain(self) -> bool:
        """Whether this is the plain benchmark (pushes answered by the trial's simulator)."""
        return (
            self.engine is None
            and self.resolution is None
            and not self.pusher_error
            and self.motion_noise is None
            and not self.measured
        )

    def fits(self, spec: EstimatorSpec) -> str | None:
        """Why ``spec`` is not run in this condition, or ``None``."""
        if not self.resets and spec.resets:
            return "needs the object put back before every push"
        return None

    def simulator(self, simulator):
        """The trial's simulator rebuilt with this condition's engine, camera and margin."""
        import simulators
        from simulators._robot import camera_frame_margin

        if self.engine is None and self.resolution is None and not self.measured:
            return simulator
        settings = simulator.settings
        if self.engine is not None:
            settings = replace(settings, engine=self.engine)
        return simulators.PushSimulator(
            simulator.shape,
            simulator.mass,
            mu_contact=simulator.mu_contact,
            resolution=self.resolution or simulator.resolution,
            margin=camera_frame_margin(
                simulator.shape, simulators.DEFAULT_CAMERA_MARGIN, simulator.com_m
            )
            if self.measured
            else simulator.margin,
            pusher_radius=simulator.pusher_radius,
            mu_floor=simulator.mu_floor,
            settings=settings,
        )

    def robot(self, simulator, rng, **options):
        """A ``simulators.SimulatedRobot`` of ``simulator`` with this condition's errors."""
        import simulators

        kwargs: dict[str, Any] = {"pusher_error": self.pusher_error, "mask_noise": self.mask_noise}
        kwargs.update(options)
        return simulators.SimulatedRobot(simulator, rng=rng, **kwargs)


#: The built-in conditions, by name.
CONDITIONS: dict[str, Condition] = {
    c.name: c
    for c in (
        Condition("exact", "every push from the initial pose, exact motions (today's benchmark)"),
        Condition("pymunk", "the pymunk rigid-body engine plays the object", engine="pymunk"),
        Condition(
            "pusher-error",
            f"the pusher {PUSHER_ERROR_M * 1e3:g} mm (std) off its path, across the push",
            pusher_error=PUSHER_ERROR_M,
        ),
        Condition(
            "motion-noise",
            f"tracking noise {math.degrees(MOTION_NOISE[0]):g} deg / {MOTION_NOISE[1] * 1e3:g} mm "
            "(std) on every motion",
            motion_noise=MOTION_NOISE,
        ),
        Condition(
            "mask-noise",
            f"noisy camera masks (outline pixels flipped with p = {MASK_NOISE:g}), motions "
            "measured from masks",
            mask_noise=MASK_NOISE,
            measured=True,
        ),
        Condition("resolution-0.1", "the camera at 0.1 cm per pixel", resolution=0.001),
        Condition("no-reset", "the object is never put back (the robot loop)", resets=False),
    )
}


def parse_condition(label: str) -> Condition:
    """The condition named by ``label``: a name, optionally with field overrides.

    Examples
    --------
    >>> parse_condition("pusher-error(pusher_error=0.001)").pusher_error
    0.001
    >>> parse_condition("fog")
    Traceback (most recent call last):
    ...
    ValueError: conditions: unknown condition 'fog'; registered: exact, mask-noise, ...
    """
    name, options = parse_call(label, "conditions", CONDITIONS)
    allowed = {f.name for f in fields(Condition)} - {"name", "description"}
    bad = sorted(set(options) - allowed)
    if bad:
        raise ValueError(
            f"conditions: {label!r} has unknown option(s) {bad}; allowed: {sorted(allowed)}"
        )
    label = label.strip() if options else name
    return replace(CONDITIONS[name], name=label, **options)


class ConditionWorld:
    """The trial's object as estimators that reset it see it under a condition.

    It answers like a :class:`simulators.PushSimulator` (``push``, ``push_many``,
    ``push_motions``, ``mask``, ``com_px``, ...), every push from the initial
    pose, with the condition's pusher error and its observation of the motion
    (measured from noisy masks, or exact with tracking noise).
    """

    def __init__(self, condition: Condition, simulator, rng, mask=None):
        self.condition = condition
        self.base = condition.simulator(simulator)
        self._rng = comcore.check_rng(rng)
        if mask is None:
            from simulators._robot import noisy_mask

            mask = self.base.mask
            if condition.measured:
                mask = noisy_mask(mask, condition.mask_noise, self._rng)
        self.mask = mask

    def with_rng(self, rng) -> ConditionWorld:
        """The same world (same first mask) with its own noise stream."""
        out = ConditionWorld.__new__(ConditionWorld)
        out.condition, out.base, out.mask = self.condition, self.base, self.mask
        out._rng = comcore.check_rng(rng)
        return out

    def __getattr__(self, name):
        if name.startswith("_") or name in ("base", "condition", "mask"):
            raise AttributeError(name)
        return getattr(self.base, name)

    def _observe(self, result):
        from simulators._robot import noisy_mask

        cond, base = self.condition, self.base
        motion = result.motion
        if cond.measured:
            after = base.mask_at(result.pose)
            d = after.data
            if d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any():
                raise ValueError("the push carried the object out of the camera's view")
            after = noisy_mask(after, cond.mask_noise, self._rng)
            motion = comcore.measure_motion(self.mask, after).motion
        if cond.motion_noise is not None:
            theta, shift = cond.motion_noise
            noise = self._rng.normal(0.0, 1.0, 3) * (
                theta,
                shift / base.resolution,
                shift / base.resolution,
            )
            motion = comcore.Motion(*(np.asarray(motion, float) + noise))
        return result._replace(motion=motion)

    def push_many(self, actions, pose=None, record: bool = False):
        """Pushes from the initial pose, executed with the condition's pusher error."""
        from simulators._robot import perturb_actions, retreat_starts

        if pose is not None:
            raise ValueError("pose: a condition's world pushes only from the initial pose")
        acts = comcore.check_actions(actions)
        base = self.base
        if self.condition.pusher_error and len(acts):
            offset = self._rng.normal(0.0, self.condition.pusher_error / base.resolution, len(acts))

            def retreat(starts, directions):
                return retreat_starts(base, base.initial_pose, starts, directions)

            inside = self._inside(acts[:, :2])
            executed = perturb_actions(acts, offset, 0.0, retreat)
            executed[inside] = acts[inside]  # a commanded start inside: refused as it is
        else:
            executed = acts
        return [self._observe(r) for r in base.push_many(executed, record=record)]

    def _inside(self, starts) -> np.ndarray:
        from simulators._deps import require_shapely

        shapely = require_shapely()
        w = self.base.to_world(starts)
        return shapely.contains_xy(shapely.Polygon(self.base.outline_at()), w[:, 0], w[:, 1])

    def push(self, action, pose=None, record: bool = False):
        """One push from the initial pose (see :meth:`push_many`)."""
        acts = comcore.check_actions(action, "action", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"action must be a single action, got {acts.shape[0]}")
        return self.push_many(acts, pose, record)[0]

    def push_motions(self, actions) -> np.ndarray:
        """Observed motions of a batch of pushes, shape (n, 3)."""
        results = self.push_many(actions)
        return np.array([r.motion for r in results], dtype=float).reshape(-1, 3)


@dataclass(frozen=True)
class ConditionConfig(BenchConfig):
    """A :class:`~comcore.bench.BenchConfig` whose trials run under one condition."""

    condition: Condition = field(default_factory=lambda: CONDITIONS["exact"])

    def specs(self) -> list[TrialSpec]:
        """The config's trials, each under :attr:`condition`."""
        return [replace(s, condition=self.condition) for s in super().specs()]


def run_conditions(
    config: BenchConfig, conditions, *, workers: int = 1, progress: bool = False, on_rows=None
) -> tuple[dict[str, BenchResult], dict[str, dict[str, str]]]:
    """Run ``config``'s trials once per condition (the same trials in each).

    Parameters
    ----------
    config : BenchConfig
    conditions : str or sequence of str or Condition
        Condition labels (``"exact,pusher-error"``, ``"all"``) or :class:`Condition` objects.
    workers, progress, on_rows
        As for :func:`comcore.bench.run_benchmark`.

    Returns
    -------
    (dict, dict)
        ``{condition: BenchResult}`` and ``{condition: {estimator: why it was not run}}``.
    """
    if isinstance(conditions, str):
        conditions = list(CONDITIONS) if conditions == "all" else split_estimators(conditions)
    parsed = [c if isinstance(c, Condition) else parse_condition(c) for c in conditions]
    if not parsed:
        raise ValueError("conditions must name at least one condition")
    names = [c.name for c in parsed]
    if len(set(names)) != len(names):
        raise ValueError(f"conditions must be distinct, got {names}")
    results, unfit = {}, {}
    base = {f.name: getattr(config, f.name) for f in fields(BenchConfig)}
    for cond in parsed:
        keep, why = [], {}
        for label in config.estimators:
            reason = cond.fits(parse_estimator(label)[0])
            if reason:
                why[label] = reason
            else:
                keep.append(label)
        unfit[cond.name] = why
        if not keep:
            continue
        cfg = ConditionConfig(**{**base, "estimators": tuple(keep)}, condition=cond)
        results[cond.name] = run_benchmark(cfg, workers=workers, progress=progress, on_rows=on_rows)
    return results, unfit


def _fmt(value, digits=3) -> str:
    return "n/a" if value is None else f"{value:.{digits}f}"


def conditions_table(results, unfit=None, command: str = "") -> str:
    """``conditions.md``: one table per condition, the estimators as rows."""
    unfit = unfit or {}
    lines = ["# Realism conditions", ""]
    if command:
        lines += ["```bash", command, "```", ""]
    lines += [
        "Every condition runs the same trials (same seeds, objects, mass distributions and "
        "friction). *region holds the CoM*: share of trials whose 90 % credible region "
        "(`Estimate.region`) contains the true CoM pixel, for estimators that report a "
        "credible region (n/a for the others). *ok > 1 cm*: share of trials that stopped "
        "with status `ok` and an error over 1 cm. *failed*: trials that ended in an error or "
        "with a push the robot could not execute.",
        "",
    ]
    for name in list(dict.fromkeys([*results, *unfit])):
        result = results.get(name)
        cond = result.config.condition if result is not None else parse_condition(name)
        lines += [f"## {name}", "", cond.description, ""]
        lines += [
            "| estimator | trials | mean error (cm) | median | mean pushes | region holds the CoM "
            "| ok > 1 cm | failed |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for label in result.config.estimators if result is not None else ():
            rows = [r for r in result.rows if r["estimator"] == label]
            err = np.array([r["error_cm"] for r in rows], float)
            pushes = np.array([r["total_pushes"] for r in rows], float)
            credible = [r for r in rows if r["credible_radius_cm"] is not None]
            cover = np.mean([bool(r["covered"]) for r in credible]) if credible else None
            bad_ok = np.mean([r["status"] == "ok" and r["error_cm"] > 1.0 for r in rows])
            failed = sum(r["status"] == "error" or (r["push_failures"] or 0) > 0 for r in rows)
            lines.append(
                f"| `{label}` | {len(rows)} | {err.mean():.3f} | {np.median(err):.3f} | "
                f"{pushes.mean():.2f} | "
                + ("n/a" if cover is None else f"{100 * cover:.0f} %")
                + f" | {100 * bad_ok:.1f} % | {failed} |"
            )
        for label, reason in unfit.get(name, {}).items():
            lines.append(f"| `{label}` | not run: {reason} | | | | | | |")
        lines.append("")
        predicted = [
            e for e in (result.config.estimators if result is not None else ())
            if parse_estimator(e)[0].uses_motions
        ]  # fmt: skip
        if predicted and not cond.plain:
            names = ", ".join(f"`{e}`" for e in predicted)
            source = (
                "this condition's observations of every candidate, each pushed from the "
                "initial pose (an optimistic stand-in for a predictor)"
                if result.config.predictor == "oracle"
                else f"the {result.config.predictor!r} predictor's, conditioned on prior "
                "pushes observed under this condition"
            )
            lines += [f"{names} work on predicted motions of every candidate: here {source}.", ""]
    return "\n".join(lines)


def run_conditions_command(args, config: BenchConfig, skipped: dict[str, str]) -> int:
    """``comcore bench --conditions ...``: run, write ``conditions.md`` and the rows.

    Writes ``conditions.md`` (one table per condition) and ``conditions.jsonl``
    (every row, with its ``condition``) into ``args.out``; returns the exit status
    (2 on a bad condition).
    """
    import json
    import shlex
    import sys
    from pathlib import Path

    if args.dask:
        print("comcore bench: --conditions runs locally (drop --dask)", file=sys.stderr)
        return 2
    try:
        labels = list(CONDITIONS) if args.conditions == "all" else split_estimators(args.conditions)
        conditions = [parse_condition(label) for label in labels]
        if not conditions:
            raise ValueError("conditions: name at least one condition")
    except ValueError as e:
        print(f"comcore bench: {e}", file=sys.stderr)
        return 2
    for label, reason in skipped.items():
        print(f"comcore bench: skipping estimator {label!r}: {reason}", file=sys.stderr)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    n = len(config.specs())
    print(
        f"comcore bench: {len(conditions)} condition(s) x {n} trials x "
        f"{len(config.estimators)} estimators on {args.workers} worker(s)"
    )
    partial = out / "conditions.partial.jsonl"
    with partial.open("w", encoding="utf-8") as stream:

        def on_rows(rows):
            stream.writelines(json.dumps(r) + "\n" for r in rows)
            stream.flush()

        try:
            results, unfit = run_conditions(
                config,
                conditions,
                workers=args.workers,
                progress=not args.no_progress,
                on_rows=on_rows,
            )
        except ValueError as e:
            print(f"comcore bench: {e}", file=sys.stderr)
            return 2
    rows = [row for result in results.values() for row in result.rows]
    with (out / "conditions.jsonl").open("w", encoding="utf-8") as stream:
        stream.writelines(json.dumps(r) + "\n" for r in rows)
    partial.unlink()
    argv = sys.argv[2:] if sys.argv[1:2] == ["bench"] else []
    command = "comcore bench " + shlex.join(argv) if argv else ""
    text = conditions_table(results, unfit, command=command)
    wall = sum(r.wall_s for r in results.values())
    text += f"\nWall time {wall:.0f} s on {args.workers} worker(s).\n"
    (out / "conditions.md").write_text(text, encoding="utf-8")
    print(text)
    print(f"conditions: {out / 'conditions.md'}; rows: {out / 'conditions.jsonl'}")
    return 0


def friction_table(rows, baseline: str | None = None) -> str:
    """A Markdown table of result rows by estimator and friction class (and both).

    Parameters
    ----------
    rows : iterable of dict or str or os.PathLike
        Result rows, or a ``conditions.jsonl`` / ``results.jsonl`` file of them.
    baseline : str, optional
        An estimator label: the "both" rows then give each mean error as a ratio of
        its, and each mean push count as a difference.

    Examples
    --------
    >>> rows = [{"estimator": "a", "friction": f, "error_cm": e, "total_pushes": 3,
    ...          "covered": True, "status": "ok", "push_failures": 0}
    ...         for f, e in (("low", 0.2), ("high", 0.4))]
    >>> print(friction_table(rows).splitlines()[-1])
    | `a` | both | 0.300 | 0.300 | 0.40 | 3.00 | 100 % | 0.0 % | 0 |
    """
    import json
    import os

    if isinstance(rows, (str, os.PathLike)):
        with open(rows, encoding="utf-8") as stream:
            rows = [json.loads(line) for line in stream if line.strip()]
    rows = list(rows)
    labels = list(dict.fromkeys(r["estimator"] for r in rows))
    frictions = [f for f in ("low", "high") if any(r["friction"] == f for r in rows)]
    lines = [
        "| estimator | friction | mean error (cm) | median | max | pushes "
        "| region holds the CoM | ok > 1 cm | failed |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    base = None
    if baseline is not None:
        ref = [r for r in rows if r["estimator"] == baseline]
        if not ref:
            raise ValueError(f"baseline {baseline!r} is not among the estimators {labels}")
        base = (
            float(np.mean([r["error_cm"] for r in ref])),
            float(np.mean([r["total_pushes"] for r in ref])),
        )
    for friction in [*frictions, "both"]:
        for label in labels:
            sel = [
                r for r in rows if r["estimator"] == label and friction in ("both", r["friction"])
            ]
            err = np.array([r["error_cm"] for r in sel], float)
            pushes = np.array([r["total_pushes"] for r in sel], float)
            mean, push = f"{err.mean():.3f}", f"{pushes.mean():.2f}"
            if friction == "both" and base is not None and label != baseline:
                mean += f" ({err.mean() / base[0]:.2f} x)"
                push += f" ({pushes.mean() - base[1]:+.2f})"
            cover = np.mean([bool(r["covered"]) for r in sel])
            bad = np.mean([r["status"] == "ok" and r["error_cm"] > 1.0 for r in sel])
            failed = sum(r["status"] == "error" or (r["push_failures"] or 0) > 0 for r in sel)
            lines.append(
                f"| `{label}` | {friction} | {mean} | {np.median(err):.3f} | {err.max():.2f} | "
                f"{push} | {100 * cover:.0f} % | {100 * bad:.1f} % | {failed} |"
            )
    return "\n".join(lines)

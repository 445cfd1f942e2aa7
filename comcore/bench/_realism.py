"""Realism conditions: the same benchmark trials with a real robot's errors (``--conditions``).

A condition changes how the trial's object answers a push, never which object
it is: every condition runs the same trials (same seeds, same mass
distributions and friction), and the estimators see the object only through
the condition. The built-in conditions (:data:`CONDITIONS`, docs/how-to/your-robot.md):

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
``mujoco``                MuJoCo's physics plays the object and a rendered camera
                          sees it (``simulators.MujocoRobot``, never reset: only
                          ``active-robot`` runs); needs ``comcore[mujoco]``, so it
                          is not among ``all`` (:data:`OPTIONAL_CONDITIONS`)
========================  =====================================================

Options change a condition's numbers: ``"pusher-error(pusher_error=0.001)"``,
``"motion-noise(motion_noise=(0.035, 0.002))"``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

import comcore

from ._registry import EstimatorSpec, parse_call

__all__ = [
    "CONDITIONS",
    "OPTIONAL_CONDITIONS",
    "Condition",
    "ConditionWorld",
    "parse_condition",
]

#: What may play the object for estimators that use a robot (``Condition.robot_engine``).
ROBOT_ENGINES = (None, "mujoco")
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
    robot_engine : str or None
        What plays the object for estimators that use a robot: ``None``, the
        trial's simulator (``simulators.SimulatedRobot``); ``"mujoco"``,
        ``simulators.MujocoRobot`` (MuJoCo's physics, masks from rendered
        frames; the trial's object, mass distribution and friction).
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
    robot_engine: str | None = None

    def __post_init__(self):
        if self.engine is not None:
            import simulators

            if self.engine not in simulators.ENGINES:
                raise ValueError(
                    f"condition {self.name!r}: engine must be one of {simulators.ENGINES}, "
                    f"got {self.engine!r}"
                )
        if self.robot_engine not in ROBOT_ENGINES:
            raise ValueError(
                f"condition {self.name!r}: robot_engine must be one of {ROBOT_ENGINES}, "
                f"got {self.robot_engine!r}"
            )
        if self.resolution is not None:
            comcore.checks.check_positive(self.resolution, f"condition {self.name!r}: resolution")
        comcore.checks.check_positive(
            self.pusher_error, f"condition {self.name!r}: pusher_error", allow_zero=True
        )
        comcore.checks.check_probability(
            self.mask_noise, f"condition {self.name!r}: mask_noise", open_high=True
        )
        if self.motion_noise is not None:
            try:
                theta, shift = (float(v) for v in self.motion_noise)
            except (TypeError, ValueError) as e:
                raise TypeError(
                    f"condition {self.name!r}: motion_noise must be (radians, metres), "
                    f"got {self.motion_noise!r}"
                ) from e
            comcore.checks.check_positive(
                theta, f"condition {self.name!r}: motion_noise[0]", allow_zero=True
            )
            comcore.checks.check_positive(
                shift, f"condition {self.name!r}: motion_noise[1]", allow_zero=True
            )
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
            and self.robot_engine is None
        )

    def fits(self, spec: EstimatorSpec) -> str | None:
        """Why ``spec`` is not run in this condition, or ``None``."""
        if not self.resets and spec.resets:
            return "needs the object put back before every push"
        return None

    def simulator(self, simulator):
        """The trial's simulator rebuilt with this condition's engine, camera and margin."""
        import simulators

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
            margin=simulators.camera_frame_margin(
                simulator.shape, simulators.DEFAULT_CAMERA_MARGIN, simulator.com_m
            )
            if self.measured
            else simulator.margin,
            pusher_radius=simulator.pusher_radius,
            mu_floor=simulator.mu_floor,
            settings=settings,
        )

    def robot(self, simulator, rng, **options):
        """A ``simulators.SimulatedRobot`` of ``simulator`` with this condition's errors.

        With ``robot_engine="mujoco"`` a ``simulators.MujocoRobot`` of the same object
        (its own camera and physics; a pusher error or mask noise is refused: MuJoCo's
        pusher follows its path and its camera's masks are what they are).
        """
        import simulators

        if self.robot_engine == "mujoco":
            errors = {k: options.get(k, getattr(self, k)) for k in ("pusher_error", "mask_noise")}
            if any(errors.values()):
                raise ValueError(f"condition {self.name!r}: the MuJoCo robot takes no {errors}")
            margin = options.get("camera_margin") or simulators.DEFAULT_CAMERA_MARGIN
            return simulators.MujocoRobot(simulator, camera_margin=margin)
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


#: Conditions that need an optional extra: named in ``--conditions``, not among ``all``.
OPTIONAL_CONDITIONS: dict[str, Condition] = {
    "mujoco": Condition(
        "mujoco",
        "MuJoCo's physics and a rendered camera play the object, never reset "
        "(simulators.MujocoRobot; comcore[mujoco])",
        resets=False,
        robot_engine="mujoco",
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
    known = {**CONDITIONS, **OPTIONAL_CONDITIONS}
    name, options = parse_call(label, "conditions", known)
    allowed = {f.name for f in fields(Condition)} - {"name", "description"}
    bad = sorted(set(options) - allowed)
    if bad:
        raise ValueError(
            f"conditions: {label!r} has unknown option(s) {bad}; allowed: {sorted(allowed)}"
        )
    label = label.strip() if options else name
    return replace(known[name], name=label, **options)


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
        self._rng = comcore.checks.check_rng(rng)
        if mask is None:
            import simulators

            mask = self.base.mask
            if condition.measured:
                mask = simulators.noisy_mask(mask, condition.mask_noise, self._rng)
        self.mask = mask

    def with_rng(self, rng) -> ConditionWorld:
        """The same world (same first mask) with its own noise stream."""
        out = ConditionWorld.__new__(ConditionWorld)
        out.condition, out.base, out.mask = self.condition, self.base, self.mask
        out._rng = comcore.checks.check_rng(rng)
        return out

    def __getattr__(self, name):
        if name.startswith("_") or name in ("base", "condition", "mask"):
            raise AttributeError(name)
        return getattr(self.base, name)

    def _observe(self, result):
        import simulators

        cond, base = self.condition, self.base
        motion = result.motion
        if cond.measured:
            after = base.mask_at(result.pose)
            d = after.data
            if d[0].any() or d[-1].any() or d[:, 0].any() or d[:, -1].any():
                raise ValueError("the push carried the object out of the camera's view")
            after = simulators.noisy_mask(after, cond.mask_noise, self._rng)
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
        import simulators

        if pose is not None:
            raise ValueError("pose: a condition's world pushes only from the initial pose")
        acts = comcore.checks.check_actions(actions)
        base = self.base
        if self.condition.pusher_error and len(acts):
            offset = self._rng.normal(0.0, self.condition.pusher_error / base.resolution, len(acts))

            def retreat(starts, directions):
                return simulators.retreat_starts(base, base.initial_pose, starts, directions)

            inside = base.contains(acts[:, :2])
            executed = simulators.perturb_actions(acts, offset, 0.0, retreat)
            executed[inside] = acts[inside]  # a commanded start inside: refused as it is
        else:
            executed = acts
        return [self._observe(r) for r in base.push_many(executed, record=record)]

    def push(self, action, pose=None, record: bool = False):
        """One push from the initial pose (see :meth:`push_many`)."""
        acts = comcore.checks.check_actions(action, "action", allow_empty=False)
        if acts.shape[0] != 1:
            raise ValueError(f"action must be a single action, got {acts.shape[0]}")
        return self.push_many(acts, pose, record)[0]

    def push_motions(self, actions) -> np.ndarray:
        """Observed motions of a batch of pushes, shape (n, 3)."""
        results = self.push_many(actions)
        return np.array([r.motion for r in results], dtype=float).reshape(-1, 3)

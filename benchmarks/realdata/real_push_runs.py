"""The runs of real_pushes.py: recorded pushes, their simulated twins, the estimators.

One object at a time: its recorded pushes (``comcore.recordings.mit_push``), the same pushes
through our simulators (the exact quasi-static engine and pymunk; uniform
pressure, the object's outline, the dataset's pusher), and per world the
estimators on all pushes, on seeded random subsets of k pushes, and the active
session choosing among seeded pools of the pushes.
"""

from __future__ import annotations

import glob
import json
import os
import time
from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

import comcore
import comcore.recordings.mit_push as mp

#: Rotation (rad) below which a push did not turn the object (the sessions' miss threshold).
TURNING = 0.01
#: The dataset's splits: choose a candidate model on train, report on test.
SPLITS = {"train": ("rect1", "ellip1", "ellip3", "hex"), "test": ("butter",)}


@dataclass
class ObjectPushes:
    """One plate's pushes as the estimators take them, and their simulated twins."""

    name: str
    recording: comcore.Recording
    mask: comcore.Mask
    com: np.ndarray  # true CoM, pixels
    actions: np.ndarray  # the pushes whose leading line hits the mask, (n, 4)
    motions: dict = field(default_factory=dict)  # world -> (n, 3)
    speeds: np.ndarray = field(default_factory=lambda: np.zeros(0))
    frames: list = field(default_factory=list)  # per push, its real poses during it (or empty)
    load_seconds: float = 0.0
    sim_seconds: dict = field(default_factory=dict)


def outlines(data_dir: str) -> dict:
    """The plates' outlines (metres) from the data folder's shapes.json (see its README)."""
    with open(os.path.join(data_dir, "shapes.json")) as f:
        shapes = json.load(f)["shapes"]
    return {name: np.asarray(s["polygon_m"], dtype=float) for name, s in shapes.items()}


#: The contacts every estimator scores (see use_contacts): the disc's radius, 0 for the line.
_contact_radius = mp.PUSHER_RADIUS


def use_contacts(kind: str) -> None:
    """Score every push at its disc's contact (``"disc"``) or at the leading line's (``"line"``).

    The estimators take the disc's contact for ``pusher_radius`` > 0 (every push the disc
    touches, grazing ones too) and the leading line's for ``pusher_radius=0``; ``"line"``
    is what they did before they scored the disc's contact (and the paper's point pusher),
    kept for comparison.
    """
    global _contact_radius
    _contact_radius = {"disc": mp.PUSHER_RADIUS, "line": 0.0}[kind]


def _contacts(mask, actions):
    if _contact_radius == 0:
        return comcore.geometry.contacts(mask, actions)
    return comcore.geometry.disc_contacts(mask, actions, _contact_radius)


def load_object(
    data_dir, name, outline, *, travel, resolution, max_speed=None, grazing=False,
    frame_rate=None,
) -> ObjectPushes:  # fmt: skip
    """The recorded pushes of one plate (every file of it under ``data_dir/abs``).

    Only the pushes whose leading line enters the mask are scored, unless ``grazing``
    (with ``use_contacts("disc")``): then every push the recording kept. ``frame_rate``
    (Hz): the pose streams during each push kept at that rate too (``obj.frames``), for
    the real world's posteriors.
    """
    start = time.perf_counter()
    files = sorted(glob.glob(os.path.join(data_dir, "abs", "*", f"*_shape={name}_*.h5")))
    if max_speed is not None:
        files = [f for f in files if mp.parse_name(f).speed <= max_speed + 1e-9]
    if not files:
        raise FileNotFoundError(f"no h5 files of {name!r} under {data_dir}/abs/*/")
    rec = mp.load_pushes(
        files, outline, travel=travel, resolution=resolution, frame_rate=frame_rate
    )
    keep = np.ones(len(rec.pushes), bool) if grazing else rec.line_hits
    obj = ObjectPushes(name, rec, rec.mask, np.asarray(rec.com), rec.actions[keep])
    if frame_rate is not None:
        obj.frames = [p.frames for p, k in zip(rec.pushes, keep) if k]
    obj.motions["real"] = rec.motions[keep]
    obj.speeds = np.array([mp.parse_name(p.name).speed for p in rec.pushes])[keep]  # nominal
    obj.load_seconds = time.perf_counter() - start
    return obj


def simulator_of(outline, mask, pusher_radius, engine: str, mu_contact: float, name="plate"):
    """A simulator of ``outline`` (uniform pressure) whose mask is ``mask``'s, pixel for pixel.

    ``engine``: ``"pymunk"``, or any other name for the quasi-static engine (``"exact"``).
    """
    import simulators

    settings = simulators.EngineSettings(engine="pymunk" if engine == "pymunk" else "quasistatic")
    sim = simulators.PushSimulator.from_polygon(
        outline, mu_contact=mu_contact, resolution=mask.resolution, pusher_radius=pusher_radius,
        settings=settings,
    )  # fmt: skip
    if not np.array_equal(sim.mask.data, mask.data):
        raise RuntimeError(f"{name}: the simulator's mask differs from the recording's")
    return sim


def simulate(obj: ObjectPushes, outline, world: str, mu_contact: float) -> None:
    """The same pushes through a simulator (uniform pressure): ``obj.motions[world]``."""
    start = time.perf_counter()
    sim = simulator_of(outline, obj.mask, mp.PUSHER_RADIUS, world, mu_contact, obj.name)
    obj.motions[world] = sim.push_motions(obj.actions)
    obj.sim_seconds[world] = time.perf_counter() - start


def score(est: comcore.Estimate, mask: comcore.Mask, com) -> dict:
    """Error (cm), whether the region holds the CoM, how far outside it lies (cm), status."""
    region = np.asarray(est.region, dtype=bool)
    holds = est.region_holds(com)
    outside = 0.0
    if not holds and region.any():
        dist = ndimage.distance_transform_edt(~region)
        r, c = (int(np.clip(round(v), 0, n - 1)) for v, n in zip(com[::-1], region.shape))
        outside = float(dist[r, c]) * mask.resolution * 100
    return {
        "error_cm": est.error_px(com) * mask.resolution * 100,
        "holds": bool(holds),
        "outside_cm": outside,
        "status": est.status,
    }


def vt_agreement(obj: ObjectPushes, world: str) -> tuple[int, int]:
    """Turning pushes whose sense the true CoM allows for some friction (unknown friction)."""
    motions = obj.motions[world]
    con = _contacts(obj.mask, obj.actions)
    agree = turning = 0
    for i, (a, m) in enumerate(zip(obj.actions, motions)):
        if abs(m[0]) < TURNING:
            continue
        turning += 1
        d = (a[2:] - a[:2]) / np.hypot(*(a[2:] - a[:2]))
        sense = int(np.sign(m[0]))
        agree += bool(comcore.vt.consistent([obj.com], con.point[i], con.normal[i], d, sense)[0])
    return agree, turning


def disc_agreement(obj: ObjectPushes, known_mu: float) -> dict:
    """The Voting Theorem on every recorded push (grazing ones too) with the disc's contact.

    Per contact model (the leading line's where it hits, the disc's), turning pushes whose
    sense the true CoM predicts at a known friction, and the same with unknown friction.
    """
    rec = obj.recording
    acts, moves = rec.actions, rec.motions
    disc = comcore.geometry.disc_contacts(rec.mask, acts, rec.pusher_radius)
    line = comcore.geometry.contacts(rec.mask, acts)
    out = {"turning": 0, "disc_known": 0, "disc_unknown": 0, "line_known": 0, "line_hits": 0}
    for i, (a, m) in enumerate(zip(acts, moves)):
        if abs(m[0]) < TURNING:
            continue
        out["turning"] += 1
        d = (a[2:] - a[:2]) / np.hypot(*(a[2:] - a[:2]))
        sense = int(np.sign(m[0]))
        predicted = comcore.vt.predicted_sense(obj.com, disc.point[i], disc.normal[i], d, known_mu)
        out["disc_known"] += int(predicted == sense)
        allowed = comcore.vt.consistent([obj.com], disc.point[i], disc.normal[i], d, sense)[0]
        out["disc_unknown"] += int(allowed)
        if line.hit[i]:
            out["line_hits"] += 1
            p = comcore.vt.predicted_sense(obj.com, line.point[i], line.normal[i], d, known_mu)
            out["line_known"] += int(p == sense)
    return out


def turn_ratio(obj: ObjectPushes, world: str = "exact") -> float:
    """Median |real rotation| / |simulated rotation| over pushes that turn in both."""
    real, sim = obj.motions["real"][:, 0], obj.motions[world][:, 0]
    both = (np.abs(real) >= TURNING) & (np.abs(sim) >= TURNING)
    return float(np.median(np.abs(real[both]) / np.abs(sim[both]))) if both.any() else float("nan")


def turn_ratio_by_speed(obj: ObjectPushes, world: str = "exact") -> dict:
    """The same ratio per nominal pusher speed (mm/s): ``{speed: [median ratio, pushes]}``."""
    real, sim = obj.motions["real"][:, 0], obj.motions[world][:, 0]
    both = (np.abs(real) >= TURNING) & (np.abs(sim) >= TURNING)
    speed = np.round(obj.speeds * 1000)  # mm/s
    out = {}
    for v in np.unique(speed[both]):
        sel = both & (speed == v)
        out[int(v)] = [float(np.median(np.abs(real[sel]) / np.abs(sim[sel]))), int(sel.sum())]
    return out


def subsets(n: int, k: int, count: int, seed: int, salt: int) -> list[np.ndarray]:
    """``count`` seeded random subsets of k of n pushes (the same in every world and model)."""
    rng = np.random.default_rng([seed, salt, k])
    return [np.sort(rng.choice(n, size=k, replace=False)) for _ in range(count)]


def posterior(obj, world, idx, model, options) -> dict:
    frames = None
    if obj.frames and world == "real":  # the real poses during each push
        frames = [obj.frames[i] for i in idx]
    est = comcore.estimate_posterior(
        obj.mask, obj.actions[idx], obj.motions[world][idx], model=model,
        pusher_radius=_contact_radius, theta_units="rad", frames=frames,  # yaw: radians
        **options,
    )  # fmt: skip
    return score(est, obj.mask, obj.com)


def progressive(obj, world, idx) -> dict:
    est = comcore.estimate_progressive(
        obj.mask, obj.actions[idx], obj.motions[world][idx], pusher_radius=_contact_radius
    )
    return score(est, obj.mask, obj.com)


def active_pool(obj, world, pool, model, options, seed) -> dict:
    """``ActiveSession`` choosing among the pool's recorded pushes, shown their motions.

    With the real world's pose streams (``obj.frames``) the session is shown each
    push's frames too (``observe(motion=..., frames=...)``), as ``posterior`` does.
    """
    options = {k: v for k, v in options.items() if k != "bootstrap"}  # estimate_posterior's
    session = comcore.ActiveSession(
        obj.mask,
        model=model,
        pusher_radius=_contact_radius,
        candidates=obj.actions[pool],
        rng=seed,
        **options,
    )
    motions = obj.motions[world][pool]
    real_frames = bool(obj.frames) and world == "real"  # the real poses during each push
    while not session.done:
        action = np.asarray(session.next_push(), dtype=float)
        j = int(np.argmin(np.abs(obj.actions[pool] - action).sum(axis=1)))
        frames = obj.frames[int(pool[j])] if real_frames else None
        session.observe(motion=motions[j], frames=frames)
        session.reset_pose()  # each recorded push started from the plate's rest pose
    out = score(session.estimate(), obj.mask, obj.com)
    out["pushes"] = len(session.actions)
    return out


def summary(runs: list[dict]) -> dict:
    """Mean error, coverage, `ok` stops outside the region by over 1 cm, statuses."""
    if not runs:
        return {}
    statuses: dict = {}
    for r in runs:
        statuses[r["status"]] = statuses.get(r["status"], 0) + 1
    out = {
        "n": len(runs),
        "error_cm": float(np.mean([r["error_cm"] for r in runs])),
        "median_cm": float(np.median([r["error_cm"] for r in runs])),
        "coverage": float(np.mean([r["holds"] for r in runs])),
        "ok_far": int(sum(r["status"] == "ok" and r["outside_cm"] > 1.0 for r in runs)),
        "statuses": statuses,
    }
    if "pushes" in runs[0]:
        out["pushes"] = float(np.mean([r["pushes"] for r in runs]))
    return out

"""The noise of one real push: the MIT push dataset's repeats of one push, measured.

The dataset (K.-T. Yu, M. Bauza, N. Fazeli, A. Rodriguez, IROS 2016) holds, besides its
pushes from many places, 2000 repeats of one push (``rect1`` on delrin, 20 mm/s, the same
contact and direction in the plate's frame, about 8.5 hours of recording): files named
``motion_surface=delrin_shape=rect1_a=0_v=20_i=0.000_s=0.700_t=0.000_rep=NNNN.h5``. Each
repeat is cut by comcore's own loader (``comcore.recordings.mit_push.load_pushes``: the
first ``--travel`` metres of pusher travel after first contact, as the likelihood sees a
push) and its outcome measured in the plate's frame at first contact (metres, ``x`` right,
``y`` up seen from above; the translation is the plate's centroid, its CoM): the rotation
(degrees, counter-clockwise positive), the translation along and across the push
direction (millimetres), and what the robot did: the push line's offset from the CoM and
its direction. Per quantity: mean, std, MAD-based robust std (1.4826 MAD), 5-95 % range,
and the drift over the recording: the least-squares slope per hour, the median std
within windows of ``--window`` consecutive repeats against the overall one, and the range
of the windows' medians.

Beside it, what comcore assumes of such a push: ``comcore.Likelihood``'s scales
(``motion_noise``: the tracker's; the model-error scales ``theta_noise`` and
``translation_error`` at this push's lever arm and displacement; the pusher's
``pusher_error`` through the limit-surface model's sensitivity to where the push meets
the plate) and the spread our simulators give for it with the benchmark's realism
conditions (``comcore.bench``'s ``pusher-error`` and ``motion-noise``, contact friction
drawn per trial from the ``low`` class) and replaying each repeat's recorded action.

The repeats are read from a folder (``REPEATS``) or straight from a git repository
(``--git-dir``, ``--commit``, ``--path``: public repository APogue/pushing_project,
commit 4fc81a71ea66d5d0c921f6300249c8b634889546, ``pushdata/delrin/rect1/normal``); the
data are never copied into this repository.

Usage::

    PYTHONPATH=. nice -n 10 python benchmarks/realdata/push_noise.py /tmp/push_repeats \\
        --json noise.json
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import comcore
import comcore.recordings.mit_push as mp

#: Robust std of a Student-t with 3 degrees of freedom (the likelihood's residuals) per unit
#: of its scale: 1.4826 times its median absolute value (0.7649); its std is sqrt(3).
T3_ROBUST_STD = 1.4826 * 0.7649
T3_STD = math.sqrt(3.0)
QUANTITIES = (
    ("rotation_deg", "rotation (deg)"),
    ("along_mm", "translation along the push (mm)"),
    ("across_mm", "translation across the push (mm)"),
    ("offset_mm", "push line's offset from the CoM (mm)"),
    ("direction_deg", "push direction (deg)"),
)


def files_from_git(git_dir: str, commit: str, path: str, dest: str, limit=None) -> list[str]:
    """Write the ``.h5`` and ``.json`` files under ``path`` at ``commit`` into ``dest``."""
    tree = subprocess.run(
        ["git", "--git-dir", git_dir, "ls-tree", "-r", commit, path.rstrip("/") + "/"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout.splitlines()
    blobs = []
    for line in tree:
        meta, name = line.split("\t", 1)
        if name.endswith((".h5", ".json")):
            blobs.append((meta.split()[2], os.path.basename(name)))
    out = []
    for sha, name in sorted(blobs, key=lambda b: b[1])[:limit]:
        target = os.path.join(dest, name)
        with open(target, "wb") as f:
            subprocess.run(
                ["git", "--git-dir", git_dir, "cat-file", "blob", sha], stdout=f, check=True
            )
        out.append(target)
    return out


def repeat_files(folder: str) -> list[str]:
    """The folder's h5 and JSON files in the order of their repeat numbers (else names)."""
    if not os.path.isdir(folder):
        raise ValueError(f"repeats must be a folder of the dataset's files, got {folder!r}")
    files = sorted(
        glob.glob(os.path.join(folder, "*.h5")) + glob.glob(os.path.join(folder, "*.json"))
    )
    if not files:
        raise ValueError(f"repeats: no .h5 or .json files in {folder!r}")

    def key(path):
        try:
            rep = mp.parse_name(path).repeat
        except ValueError:
            rep = None
        return (rep is None, rep or 0, os.path.basename(path))

    return sorted(files, key=key)


def outcomes(rec: comcore.Recording, direction=None) -> dict:
    """Per kept push: time (h), rotation (deg), translation along/across (mm), the push line.

    Lengths in the plate's frame at first contact (``y`` up); ``direction`` (a unit vector in
    that frame) is the push direction the translation is resolved along (default: the
    pushes' median).
    """
    res = rec.mask.resolution
    acts = rec.actions
    start, end = rec.object_from_pixels(acts[:, :2]), rec.object_from_pixels(acts[:, 2:])
    unit = (end - start) / np.linalg.norm(end - start, axis=1, keepdims=True)
    if direction is None:
        direction = np.median(unit, axis=0)
        direction = direction / np.linalg.norm(direction)
    across_unit = np.array([-direction[1], direction[0]])
    com = rec.object_from_pixels(np.array([rec.com]))[0] if rec.com is not None else np.zeros(2)
    motions = rec.motions
    shift = np.column_stack([motions[:, 1] * res, -motions[:, 2] * res])  # metres, y up
    # the CoM's signed distance from each push line (positive: left of the push direction)
    lever = unit[:, 0] * (com[1] - start[:, 1]) - unit[:, 1] * (com[0] - start[:, 0])
    times = np.array([p.start_time for p in rec.pushes])
    return {
        "time_h": (times - times.min()) / 3600.0,
        "rotation_deg": np.degrees(motions[:, 0]),
        "along_mm": shift @ direction * 1e3,
        "across_mm": shift @ across_unit * 1e3,
        "offset_mm": lever * 1e3,
        "direction_deg": np.degrees(np.arctan2(unit[:, 1], unit[:, 0])),
        "direction": direction,
    }


def spread(values, time_h, window: int) -> dict:
    """Mean, std, robust std, 5-95 %, slope per hour, and the spread within windows."""
    x = np.asarray(values, dtype=float)
    robust = 1.4826 * float(np.median(np.abs(x - np.median(x))))
    out = {
        "n": len(x),
        "mean": float(x.mean()),
        "median": float(np.median(x)),
        "std": float(x.std(ddof=1)) if len(x) > 1 else 0.0,
        "robust_std": robust,
        "p5": float(np.percentile(x, 5)),
        "p95": float(np.percentile(x, 95)),
    }
    hours = float(np.ptp(time_h)) if len(x) else 0.0
    out["hours"] = hours
    out["slope_per_h"] = float(np.polyfit(time_h, x, 1)[0]) if len(x) > 2 and hours > 0 else 0.0
    chunks = [x[i : i + window] for i in range(0, len(x) - window + 1, window)]
    if chunks:
        out["window_std"] = float(np.median([c.std(ddof=1) for c in chunks]))
        out["window_robust_std"] = float(
            np.median([1.4826 * np.median(np.abs(c - np.median(c))) for c in chunks])
        )
        medians = [float(np.median(c)) for c in chunks]
        out["window_medians"] = medians
        out["window_median_range"] = max(medians) - min(medians)
    return out


def likelihood_scales(rec, real: dict, likelihood: comcore.Likelihood, mu: float) -> dict:
    """The likelihood's scales as they act on this push, in degrees and millimetres.

    The model-error scales at the push's median lever arm (the CoM's distance to the push
    line: a push along the side's normal keeps its force on that line for any friction) and
    median displacement; ``motion_noise``; the two in quadrature as the likelihood adds them
    (:func:`comcore.active._motion_term.motion_terms`); and ``pusher_error`` through the
    limit-surface model's change of the rotation per metre the push line moves across.
    """
    lever_m = float(np.median(np.abs(real["offset_mm"]))) / 1e3
    moved_m = float(np.median(np.hypot(real["along_mm"], real["across_mm"]))) / 1e3
    theta_model, moved_model = likelihood.model_error_scales(lever_m, moved_m)
    track_theta, track_m = likelihood.motion_noise
    sens = model_sensitivity(rec, real, mu)
    out = {
        "lever_mm": lever_m * 1e3,
        "displacement_mm": moved_m * 1e3,
        "model_theta_deg": math.degrees(float(theta_model)),
        "model_translation_mm": float(moved_model) * 1e3,
        "motion_noise_deg": math.degrees(track_theta),
        "motion_noise_mm": track_m * 1e3,
        "pusher_error_mm": likelihood.pusher_error * 1e3,
        **sens,
    }
    out["scored_theta_deg"] = math.hypot(out["model_theta_deg"], out["motion_noise_deg"])
    out["scored_translation_mm"] = math.hypot(out["model_translation_mm"], out["motion_noise_mm"])
    out["pusher_theta_deg"] = abs(sens["dtheta_deg_per_mm"]) * out["pusher_error_mm"]
    return out


def model_sensitivity(rec, real: dict, mu: float) -> dict:
    """The limit-surface model on the median push: its motion, and per mm across the push."""
    model = comcore.LimitSurfaceModel(pusher_radius=rec.pusher_radius)
    action = np.median(rec.actions, axis=0)[None]
    d = np.radians(np.median(real["direction_deg"]))
    across_px = np.array([-math.sin(d), -math.cos(d)])  # the left normal, in pixels (y down)
    step_px = 1.0  # one pixel of CoM shift each way
    com = np.array(rec.com, dtype=float)
    coms = np.array([com, com + step_px * across_px, com - step_px * across_px])
    pred = model.predict_hypotheses(rec.mask, action, coms, mu)[:, 0]
    res = rec.mask.resolution
    # a push moved across by +s is the same push on a CoM moved by -s
    dtheta = (pred[2, 0] - pred[1, 0]) / (2 * step_px * res * 1e3)
    return {
        "lsm_rotation_deg": math.degrees(float(pred[0, 0])),
        "lsm_translation_mm": float(np.hypot(*pred[0, 1:]) * res * 1e3),
        "dtheta_deg_per_mm": math.degrees(float(dtheta)),
    }


def simulated(rec, outline, real: dict, engine: str, samples: int, mu: float, seed: int) -> dict:
    """Spreads our simulators give for this push: its recorded actions replayed, and the
    median action under the benchmark's realism conditions (pusher error, tracking noise,
    contact friction per trial from the ``low`` class)."""
    from real_push_runs import simulator_of  # this script's folder is on sys.path

    import simulators
    from comcore.bench._realism import MOTION_NOISE, PUSHER_ERROR_M

    rng = np.random.default_rng([seed, 30])

    def build(mu_contact):
        return simulator_of(outline, rec.mask, rec.pusher_radius, engine, mu_contact, "rect1")

    n = len(rec.pushes)
    pick = np.unique(np.linspace(0, n - 1, min(samples, n)).round().astype(int))
    start = time.perf_counter()
    replay = _as_outcomes(rec, build(mu).push_motions(rec.actions[pick]), real, pick)
    lo, hi = simulators.FRICTION_CLASSES["low"]
    mus = np.round(rng.uniform(lo, hi, samples), 2)
    median_action = np.median(rec.actions, axis=0)
    offsets = rng.normal(0.0, PUSHER_ERROR_M / rec.mask.resolution, samples)
    actions = simulators.perturb_actions(
        np.repeat(median_action[None], samples, axis=0), offsets, np.zeros(samples)
    )
    motions = np.zeros((samples, 3))
    for m in np.unique(mus):
        idx = np.flatnonzero(mus == m)
        motions[idx] = build(float(m)).push_motions(actions[idx])
    noise_theta, noise_m = MOTION_NOISE
    motions[:, 0] += rng.normal(0.0, noise_theta, samples)
    motions[:, 1:] += rng.normal(0.0, noise_m / rec.mask.resolution, (samples, 2))
    conditions = _as_outcomes(rec, motions, real, None)
    return {
        "replay": replay,
        "conditions": conditions,
        "seconds": time.perf_counter() - start,
        "conditions_desc": (
            f"median action, pusher {PUSHER_ERROR_M * 1e3:g} mm across (std), contact "
            f"friction U({lo}, {hi}), tracking {math.degrees(noise_theta):g} deg / "
            f"{noise_m * 1e3:g} mm"
        ),
    }


def _as_outcomes(rec, motions, real, pick) -> dict:
    res = rec.mask.resolution
    direction = real["direction"]
    across_unit = np.array([-direction[1], direction[0]])
    shift = np.column_stack([motions[:, 1] * res, -motions[:, 2] * res])
    out = {
        "rotation_deg": np.degrees(motions[:, 0]),
        "along_mm": shift @ direction * 1e3,
        "across_mm": shift @ across_unit * 1e3,
    }
    out["time_h"] = real["time_h"][pick] if pick is not None else np.zeros(len(motions))
    return out


def _row(label, s) -> str:
    win = (
        f"{s['window_robust_std']:.2f} / {s['window_median_range']:.2f}"
        if "window_robust_std" in s
        else "-"
    )
    return (
        f"| {label} | {s['median']:.2f} | {s['std']:.2f} | {s['robust_std']:.2f} | "
        f"{s['p5']:.2f} to {s['p95']:.2f} | {s['slope_per_h']:+.3f} | {win} |"
    )


def report(results: dict, args) -> str:
    """The tables, as markdown."""
    lines = []
    for travel, r in results["travels"].items():
        lines += [
            f"## {float(travel) * 100:g} cm of pusher travel after contact: {r['n_kept']} repeats "
            f"kept of {r['n_files']}, {r['hours']:.1f} h",
            "",
            f"| quantity | median | std | robust std | 5-95 % | slope per hour | within "
            f"{args.window}: robust std / range of medians |",
            "|---|---|---|---|---|---|---|",
        ]
        lines += [_row(label, r["real"][key]) for key, label in QUANTITIES]
        s = r["scales"]
        lines += [
            "",
            f"The likelihood's scales on this push (lever {s['lever_mm']:.1f} mm, displacement "
            f"{s['displacement_mm']:.1f} mm; Student-t scales, whose robust std is "
            f"{T3_ROBUST_STD:.3f} x the scale):",
            "",
            "| term | rotation (deg) | translation (mm) |",
            "|---|---|---|",
            f"| `motion_noise` (the tracker's) | {s['motion_noise_deg']:.2f} | "
            f"{s['motion_noise_mm']:.2f} |",
            f"| model error (`theta_noise`, `translation_error`) | {s['model_theta_deg']:.2f} | "
            f"{s['model_translation_mm']:.2f} |",
            f"| both, as scored (in quadrature) | {s['scored_theta_deg']:.2f} | "
            f"{s['scored_translation_mm']:.2f} |",
            f"| `pusher_error` {s['pusher_error_mm']:g} mm through the model "
            f"({s['dtheta_deg_per_mm']:+.2f} deg per mm across) | {s['pusher_theta_deg']:.2f} | |",
            f"| the model's own motion (`LimitSurfaceModel`, mu {args.mu_contact}) | "
            f"{s['lsm_rotation_deg']:.2f} | {s['lsm_translation_mm']:.2f} |",
        ]
        if r.get("sims"):
            lines += [
                "",
                "The simulators on the same push (std / robust std / 5-95 %):",
                "",
                "| engine | what varies | rotation (deg) | along (mm) | across (mm) |",
                "|---|---|---|---|---|",
            ]
            for engine, sim in r["sims"].items():
                for kind, what in (
                    ("replay", f"each repeat's recorded action, mu {args.mu_contact}"),
                    ("conditions", sim["conditions_desc"]),
                ):
                    cells = [
                        f"{q['std']:.2f} / {q['robust_std']:.2f} / {q['p5']:.1f} to {q['p95']:.1f}"
                        for q in (sim[kind][k] for k in ("rotation_deg", "along_mm", "across_mm"))
                    ]
                    lines.append(f"| {engine} | {what} | " + " | ".join(cells) + " |")
        lines.append("")
    return "\n".join(lines)


def run(files, args) -> dict:
    """Every measurement, per window length."""
    likelihood = comcore.Likelihood()
    outline = mp.OUTLINES[args.shape]
    out = {"n_files": len(files), "travels": {}}
    for travel in args.travel:
        rec = mp.load_pushes(files, outline, travel=travel, resolution=args.resolution)
        if len(rec.pushes) < 3:
            raise ValueError(
                f"only {len(rec.pushes)} of {len(files)} files give a push of {travel} m: "
                f"{rec.report()}"
            )
        real = outcomes(rec)
        r = {
            "n_files": len(files),
            "n_kept": len(rec.pushes),
            "skipped": [s._asdict() for s in rec.skipped],
            "hours": float(np.ptp(real["time_h"])),
            "real": {key: spread(real[key], real["time_h"], args.window) for key, _ in QUANTITIES},
            "scales": likelihood_scales(rec, real, likelihood, args.mu_contact),
            "sims": {},
        }
        for engine in [e for e in args.sims.split(",") if e]:
            try:
                sim = simulated(
                    rec, outline, real, engine, args.sim_samples, args.mu_contact, args.seed
                )
            except ImportError as e:
                print(f"{engine}: left out ({e})", file=sys.stderr)
                continue
            r["sims"][engine] = {
                kind: {
                    k: spread(sim[kind][k], sim[kind]["time_h"], args.window)
                    for k in ("rotation_deg", "along_mm", "across_mm")
                }
                for kind in ("replay", "conditions")
            }
            r["sims"][engine]["conditions_desc"] = sim["conditions_desc"]
            r["sims"][engine]["seconds"] = sim["seconds"]
        out["travels"][f"{travel:g}"] = r
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("repeats", nargs="?", help="folder of the repeats' files (h5 or JSON)")
    p.add_argument("--git-dir", help="read the files from this git directory instead")
    p.add_argument("--commit", help="with --git-dir: the commit")
    p.add_argument("--path", help="with --git-dir: the folder in that commit")
    p.add_argument("--travel", default="0.03,0.1", help="windows, metres after first contact")
    p.add_argument("--shape", default="rect1", choices=sorted(mp.OUTLINES), help="the plate")
    p.add_argument("--resolution", type=float, default=0.0025, help="metres per pixel")
    p.add_argument("--window", type=int, default=100, help="repeats per drift window")
    p.add_argument("--limit", type=int, default=None, help="the first N repeats only")
    p.add_argument("--sims", default="exact,pymunk", help="engines ('' for none)")
    p.add_argument("--sim-samples", type=int, default=200, help="simulated pushes per kind")
    p.add_argument("--mu-contact", type=float, default=0.23, help="contact friction, replay")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", help="write every figure to this file")
    args = p.parse_args(argv)
    if (args.repeats is None) == (args.git_dir is None):
        p.error("give either the repeats folder or --git-dir with --commit and --path")
    if args.git_dir and not (args.commit and args.path):
        p.error("--git-dir needs --commit and --path")
    try:
        args.travel = [float(t) for t in args.travel.split(",")]
    except ValueError:
        p.error(f"--travel must be metres separated by commas, got {args.travel!r}")
    if args.window < 2:
        p.error(f"--window must be at least 2, got {args.window}")
    wall = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        if args.git_dir:
            files = files_from_git(args.git_dir, args.commit, args.path, tmp, args.limit)
        else:
            files = repeat_files(args.repeats)[: args.limit]
        results = run(files, args)
    results["wall_s"] = time.perf_counter() - wall
    text = report(results, args)
    print(f"# The noise of one real push ({len(files)} files; wall {results['wall_s']:.0f} s)\n")
    print(text)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), **results}, f, indent=1, default=_plain)
    return 0


def _plain(x):
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    return str(x)


if __name__ == "__main__":
    sys.exit(main())

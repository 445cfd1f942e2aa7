"""How many frames of a push the session reads: ``MAX_PATH_FRAMES`` against the robot loop.

Run: ``PYTHONPATH=. python benchmarks/calibration/path_frames.py [--frames 4,8,16]
[--seed 1] [--conditions exact,pymunk,mask-noise] [--objects all] [--trials 1]
[--frame-rate 10] [--workers 2] [--out path-frames]``.

For each count, ``comcore.active._path.MAX_PATH_FRAMES`` is set to it (the session then
reads at most that many frames of each push, evenly spread in travel, and drops the
rest as ``"thinned"``) and ``comcore bench`` runs ``active-robot(frame_rate=...)`` under
each condition (``--workers`` processes forked after the setting, so they share it). The
table printed: per condition and count, the trials, mean and median error, pushes, how
often the 90 % region holds the CoM, and the share of ``ok`` stops more than 1 cm off,
read from each run's ``conditions.jsonl`` (the bench's own report goes to stderr). The
bench seeds each run's session by the estimator's label, so the rate is written as the
docs write it (``frame_rate=10``). The default was chosen on seed 1 and reported
on seeds 0 and 2 (docs/explanation/calibration.md).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
from pathlib import Path

import numpy as np

import comcore.active._path as path_module
from comcore.cli import main as comcore_main


def run(count: int, condition: str, args) -> list[dict]:
    """One ``comcore bench`` run with at most ``count`` frames read; its rows."""
    out = Path(args.out) / f"frames{count}-seed{args.seed}-{condition}"
    path_module.MAX_PATH_FRAMES = count
    # the label as the docs write it (10, not 10.0): the bench seeds a run's session by its label
    label = f"active-robot(frame_rate={args.frame_rate:g})"
    with contextlib.redirect_stdout(sys.stderr):  # the bench's own report: not the table
        code = comcore_main([
            "bench", "--objects", args.objects, "--trials", str(args.trials),
            "--seed", str(args.seed), "--workers", str(args.workers), "--conditions", condition,
            "--estimators", label, "--no-figures", "--no-progress", "--out", str(out),
        ])  # fmt: skip
    if code:
        raise SystemExit(f"comcore bench failed ({code}) for {count} frames, {condition}")
    rows = [json.loads(line) for line in (out / "conditions.jsonl").read_text().splitlines()]
    return [r for r in rows if r.get("condition", condition) == condition]


def summary(rows: list[dict]) -> str:
    err = np.array([r["error_cm"] for r in rows], float)
    pushes = np.array([r["pushes_used"] for r in rows], float)
    held = [r["covered"] for r in rows if r.get("covered") is not None]
    far = [r.get("status") == "ok" and r["error_cm"] > 1.0 for r in rows]
    return (
        f"{len(rows)} | {err.mean():.3f} | {np.median(err):.3f} | {pushes.mean():.2f} | "
        f"{100 * np.mean(held):.0f} % | {100 * np.mean(far):.1f} %"
    )


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", default="4,8,16")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--conditions", default="exact,pymunk,mask-noise")
    parser.add_argument("--objects", default="all")
    parser.add_argument("--trials", type=int, default=1)
    parser.add_argument("--frame-rate", type=float, default=10.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default="path-frames")
    args = parser.parse_args(argv)
    lines = [
        "| condition | frames read | trials | mean error (cm) | median | pushes | "
        "90 % region holds the CoM | `ok` > 1 cm |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for condition in args.conditions.split(","):
        for count in (int(v) for v in args.frames.split(",")):
            lines.append(f"| {condition} | {count} | {summary(run(count, condition, args))} |")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""Draw docs/img/session_log.png: what a comcore.ros.SessionLog holds, read back from its file.

One active session on ``simulators.SimulatedRobot`` is logged step by step
(:class:`comcore.ros.SessionLog`: an MCAP file of standard ROS 2 messages, the one
Foxglove and Rerun open); the file is then read back with
:func:`comcore.ros.read_session_log` and each step drawn as a viewer's image panel shows
it, in the first mask's pixels (where the posterior lives): the first camera frame, the
posterior over the CoM (brighter: likelier), the 90 % region's outline, the pushes so far
and the estimate with the true CoM, cropped to the object's neighbourhood.

Run: ``PYTHONPATH=. python benchmarks/figures/session_log_figure.py``
(``--out docs/img/session_log.png``, the default)
(needs comcore[sim,plot,ros]). The tests run it into a temporary folder.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

import comcore
import simulators


def log_session(folder: Path, args) -> tuple[Path, tuple[float, float], float]:
    """Run and log one session; the log's path, the true CoM (first mask's px), resolution."""
    robot = simulators.SimulatedRobot(
        simulators.random_simulator(args.object, args.friction, rng=args.seed), rng=args.seed
    )
    mask = robot.camera_mask()
    truth = robot.true_com_px
    truth = truth() if callable(truth) else truth
    session = comcore.ActiveSession(mask, pusher_radius=0.004, rng=args.seed)
    path = folder / "session"
    with comcore.ros.SessionLog(path) as log:
        log.step(session, mask=mask, frame=_frame(mask), time=0.0)
        while not session.done:
            robot.execute(session.next_push())
            mask = robot.camera_mask()
            session.observe(mask)
            log.step(session, mask=mask, frame=_frame(mask), time=float(len(session.actions)))
    return path, tuple(truth), mask.resolution


def _frame(mask) -> np.ndarray:
    """A grey camera frame of the mask (a dark object on a light table)."""
    grey = np.where(mask.data, 60, 200).astype(np.uint8)
    return np.repeat(grey[..., None], 3, axis=2)


def draw(steps, truth, resolution: float, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = steps[-4:]
    rows, cols = np.nonzero(steps[0]["mask"])
    pad = 12
    window = (cols.min() - pad, cols.max() + pad, rows.max() + pad, rows.min() - pad)
    fig, axes = plt.subplots(1, len(shown), figsize=(3.0 * len(shown), 3.3), squeeze=False)
    for ax, step in zip(axes[0], shown):
        ax.imshow(steps[0]["camera"], alpha=0.45)
        heat = np.ma.masked_less(step["posterior"], 4)  # the posterior's tail: not drawn
        ax.imshow(heat, cmap="magma", vmin=0, vmax=255, alpha=0.8)
        ax.contour(step["region"] > 0, levels=[0.5], colors="cyan", linewidths=1.0)
        for x0, y0, x1, y1 in step["pushes"] / resolution:
            ax.annotate("", (x1, y1), (x0, y0), arrowprops={"arrowstyle": "->", "color": "orange"})
        ex, ey = np.asarray(step["estimate"]) / resolution
        ax.plot(ex, ey, "x", color="cyan", markersize=8, label="estimate")
        ax.plot(*truth, "+", color="lime", markersize=10, label="true CoM")
        status = step["status"]
        ax.set_title(f"t = {step['time']:.0f} s: {status['n_pushes']} pushes, {status['status']}",
                     fontsize=9)
        ax.set_xlim(window[0], window[1])
        ax.set_ylim(window[2], window[3])
        ax.set_axis_off()
    axes[0][0].legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--object", default="Obj2")
    parser.add_argument("--friction", default="low", choices=("low", "high"))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=Path("docs/img/session_log.png"))
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        path, truth, resolution = log_session(Path(folder), args)
        steps = comcore.ros.read_session_log(path)
    draw(steps, truth, resolution, args.out)
    print(f"{len(steps)} steps logged; drawn to {args.out}")


if __name__ == "__main__":
    main()

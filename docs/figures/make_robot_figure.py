"""Draw docs/img/robot_session.png: an ActiveSession on a simulated robot's camera frames.

The loop of docs/tutorials/robot-session.md ("The loop"): benchmark object Obj2 (low friction,
rng 0) on ``simulators.SimulatedRobot`` (never reset, the pusher 1 mm (std) off its path),
grey camera frames turned into masks by ``comcore.mask_from_image``, the default session. Left: the
camera's last frame, cropped to where the object went, with its outline before every push,
the pushes as the session asked for them (camera pixels, numbered in order: each on the
object where the push before left it) and the CoM now, estimated and true. Right:
``comcore.plot.plot_estimate`` of the session's estimate (the first image's frame, framed on
the object by default).

Run: ``python docs/figures/make_robot_figure.py [OUT.png]`` (needs comcore[sim,plot]); the default
output is docs/img/robot_session.png. The tests run it into a temporary folder.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import comcore

OBJECT, FRICTION, SEED = "Obj2", "low", 0


def camera_image(robot) -> np.ndarray:
    """A grey uint8 frame, as a camera driver hands it: a dark object on a light table."""
    mask = robot.camera_mask()
    noise = np.random.default_rng(robot.pushes).normal(0.0, 8.0, mask.shape)
    return np.clip(np.where(mask.data, 60.0, 190.0) + noise, 0, 255).astype(np.uint8)


def run_session():
    """The loop of docs/tutorials/robot-session.md; returns what the figure shows."""
    import simulators

    robot = simulators.SimulatedRobot(
        simulators.random_simulator(OBJECT, friction=FRICTION, rng=SEED),
        pusher_error=0.001,
        rng=SEED,
    )
    first = comcore.mask_from_image(camera_image(robot), resolution=robot.resolution)
    session = comcore.ActiveSession(first, pusher_radius=0.004, rng=SEED)
    seen = []  # the mask after each push
    while not session.done:
        robot.execute(session.next_push())
        last = camera_image(robot)
        seen.append(comcore.mask_from_image(last, resolution=robot.resolution))
        session.observe(seen[-1])
    return {
        "first": first,
        "between": seen[:-1],  # the object before pushes 2, 3, ...
        "last_image": last,
        "estimate": session.estimate(),
        "status": session.status,
        "com_now": np.asarray(session.com_in_camera(), float),
        "true_now": np.asarray(robot.com_in_camera, float),
        "true_first": np.asarray(robot.true_com_px, float),
        "resolution": robot.resolution,
    }


def _camera_panel(ax, run) -> None:
    """The last camera frame around the object's path, the pushes as asked, the CoM now."""
    import comcore.plot

    first, image, est = run["first"], run["last_image"], run["estimate"]
    pushes = np.array([p.camera_action for p in est.pushes if p.outcome != "failed"], float)
    ax.imshow(image, cmap="gray", vmin=0, vmax=255, interpolation="nearest")
    ax.contour(first.data.astype(float), levels=[0.5], colors=["tab:orange"],
               linestyles="dashed", linewidths=1.2)  # fmt: skip
    shades = ["tab:blue", "tab:purple", "tab:cyan", "tab:olive", "tab:pink", "tab:brown"]
    for k, mask in enumerate(run["between"]):
        ax.contour(mask.data.astype(float), levels=[0.5], colors=[shades[k % len(shades)]],
                   linestyles="dashdot", linewidths=1.3)  # fmt: skip
    for sx, sy, ex, ey in pushes:
        ax.annotate("", (ex, ey), (sx, sy), zorder=3,
                    arrowprops={"arrowstyle": "-|>", "color": "tab:red", "lw": 1.4,
                                "shrinkA": 0, "shrinkB": 0})  # fmt: skip
    now, truth = run["com_now"], run["true_now"]
    rows, cols = np.nonzero(image < 125)  # the object now (dark)
    frows, fcols = np.nonzero(np.logical_or.reduce([m.data for m in (first, *run["between"])]))
    xs = np.concatenate([cols, fcols, pushes[:, 0], pushes[:, 2]])
    ys = np.concatenate([rows, frows, pushes[:, 1], pushes[:, 3]])
    pad = 0.12 * max(np.ptp(xs), np.ptp(ys))
    size = 0.045 * (max(np.ptp(xs), np.ptp(ys)) + 2 * pad)
    places = comcore.plot.number_positions(pushes, size, avoid=[now, truth])
    for k, (x, y) in enumerate(places):
        bbox = {"boxstyle": "circle,pad=0.2", "fc": "tab:red", "ec": "white"}
        ax.text(x, y, str(k + 1), color="white", fontsize=7, ha="center", va="center",
                zorder=6, bbox=bbox)  # fmt: skip
    for point, marker, color, label in (
        (now, "x", "black", f"CoM now, estimated ({now[0]:.1f}, {now[1]:.1f})"),
        (truth, "+", "tab:green", f"CoM now, true ({truth[0]:.1f}, {truth[1]:.1f})"),
    ):
        ax.plot(*point, marker, color="white", ms=14, mew=5.0, zorder=5)
        ax.plot(*point, marker, color=color, ms=12, mew=2.5, zorder=5, label=label)
    from matplotlib.lines import Line2D

    ax.add_line(Line2D([], [], color="tab:orange", ls="--", label="the object before push 1"))
    for k in range(len(run["between"])):
        color = shades[k % len(shades)]
        ax.add_line(Line2D([], [], color=color, ls="-.", label=f"the object before push {k + 2}"))
    ax.add_line(Line2D([], [], color="tab:red", marker=">", label="pushes asked for, in order"))
    x0, x1 = min(xs.min(), places[:, 0].min()) - pad, max(xs.max(), places[:, 0].max()) + pad
    y0, y1 = min(ys.min(), places[:, 1].min()) - pad, max(ys.max(), places[:, 1].max()) + pad
    ax.set_xlim(x0, x1)
    ax.set_ylim(y1, y0)
    ax.set_xlabel("x (camera pixels)")
    ax.set_ylabel("y (camera pixels, down)")
    h, w = image.shape
    ax.set_title(f"the camera now ({w} x {h} px frame, cropped)", fontsize=9)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8, ncol=2)


def main(out: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    import comcore.plot

    run = run_session()
    est = run["estimate"]
    fig = Figure(figsize=(11.5, 6.0), dpi=110, layout="constrained")
    panels = fig.subfigures(1, 2, width_ratios=[1.0, 1.1])  # each laid out on its own
    left, right = panels[0].add_subplot(), panels[1].add_subplot()
    _camera_panel(left, run)
    error_cm = 100 * run["resolution"] * est.error_px(run["true_first"])
    title = (
        f"the estimate in the first image: status {run['status']}, "
        f"{len(est.pushes)} pushes, {error_cm:.2f} cm off"
    )
    comcore.plot.plot_estimate(run["first"], est, truth=run["true_first"], ax=right, title=title)
    fig.suptitle(
        f"ActiveSession on a simulated robot's camera ({OBJECT}, {FRICTION} friction): "
        "python docs/figures/make_robot_figure.py",
        fontsize=10,
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out)
    print(f"saved {out}: status {run['status']}, error {error_cm:.2f} cm")
    return out


if __name__ == "__main__":
    root = Path(__file__).resolve().parents[2]
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else root / "docs" / "img" / "robot_session.png")

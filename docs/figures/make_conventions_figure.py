"""Draw docs/img/conventions.png: the pixel frame, the sign of theta, a push and its sides.

Run: ``python docs/figures/make_conventions_figure.py`` (needs matplotlib).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import comcore


def main(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    img = np.zeros((30, 40), bool)
    img[6:24, 8:16] = True
    img[18:24, 8:30] = True
    mask = comcore.Mask(img)
    action = comcore.Action(2, 12, 14, 12)
    ccw, cw = comcore.geometry.split_by_line(mask, action)
    shown = np.ones((*img.shape, 3))
    shown[img] = (0.75, 0.75, 0.75)
    shown[ccw] = (0.65, 0.8, 1.0)
    shown[cw] = (1.0, 0.8, 0.65)

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    ax = axes[0]
    ax.imshow(shown, origin="upper")
    ax.set_title("pixel frame: x = column, y = row (down)")
    ax.annotate("", xy=(10, 1), xytext=(1, 1), arrowprops={"arrowstyle": "->", "lw": 2})
    ax.annotate("", xy=(1, 10), xytext=(1, 1), arrowprops={"arrowstyle": "->", "lw": 2})
    ax.text(10.5, 1.8, "+x", fontsize=11)
    ax.text(1.5, 11.5, "+y", fontsize=11)
    ax.annotate(
        "",
        xy=action.end,
        xytext=action.start,
        arrowprops={"arrowstyle": "->", "lw": 2.5, "color": "k"},
    )
    ax.text(2, 14.3, "Action (push)", fontsize=10)
    ax.text(20, 9, "CCW side of the push\n(signed distance > 0)", color=(0.1, 0.3, 0.8), fontsize=9)
    ax.text(20, 27.5, "CW side", color=(0.7, 0.3, 0.0), fontsize=9)
    cx, cy = mask.centroid
    ax.plot(cx, cy, "k+", ms=12, mew=2)
    ax.text(cx + 0.7, cy - 0.7, "area centroid", fontsize=9)

    ax = axes[1]
    ax.imshow(img, origin="upper", cmap="Greys", alpha=0.25)
    pts = mask.pixels
    moved = comcore.apply_motion(pts, np.deg2rad(30), (4.0, -2.0), mask.centroid)
    ax.scatter(
        moved[:, 0],
        moved[:, 1],
        s=4,
        c="tab:blue",
        label="after Motion(theta=+30 deg, tx=4, ty=-2)",
    )
    ax.set_xlim(-0.5, 39.5)
    ax.set_ylim(29.5, -0.5)
    t = np.linspace(0.2, 1.6, 30)
    ax.plot(cx + 9 * np.cos(t), cy - 9 * np.sin(t), color="tab:red", lw=2)
    ax.annotate(
        "",
        xy=(cx + 9 * np.cos(1.7), cy - 9 * np.sin(1.7)),
        xytext=(cx + 9 * np.cos(1.6), cy - 9 * np.sin(1.6)),
        arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 2},
    )
    ax.text(cx + 7, cy - 9, "theta > 0:\ncounter-clockwise\non screen", color="tab:red", fontsize=9)
    ax.set_title("theta > 0 turns the object CCW as seen on screen")
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(
        Path(sys.argv[1])
        if len(sys.argv) > 1
        else Path(__file__).resolve().parents[1] / "img" / "conventions.png"
    )

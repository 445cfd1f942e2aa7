"""Canonical shapes shared by the tests."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import settings

import comcore

# MuJoCo picks its GL backend at its first import, which any test module may do (an
# importorskip at collection): offscreen EGL unless the environment chose one.
os.environ.setdefault("MUJOCO_GL", "egl")
if os.environ["MUJOCO_GL"] == "egl":
    os.environ.setdefault("EGL_PLATFORM", "surfaceless")

# No per-example deadline (the machine may be busy); CI replays a fixed set of examples.
settings.register_profile("default", deadline=None)
settings.register_profile("ci", deadline=None, derandomize=True)
settings.load_profile("ci" if os.environ.get("CI") else "default")


def disk_image(radius: int = 20, margin: int = 6) -> np.ndarray:
    side = 2 * (radius + margin) + 1
    yy, xx = np.mgrid[0:side, 0:side]
    c = radius + margin
    return (xx - c) ** 2 + (yy - c) ** 2 <= radius**2


@pytest.fixture
def square_mask() -> comcore.Mask:
    """A 30 x 30 square with a 10-pixel margin: object pixels 10..39."""
    return comcore.Mask(np.pad(np.ones((30, 30), bool), 10), resolution=0.0025)


@pytest.fixture
def disk_mask() -> comcore.Mask:
    """A disk of radius 20 px centred at (26, 26)."""
    return comcore.Mask(disk_image(), resolution=0.0025)


@pytest.fixture
def l_mask() -> comcore.Mask:
    """An asymmetric L shape (no rotational symmetry), for frame tests."""
    img = np.zeros((40, 50), bool)
    img[5:35, 5:15] = True
    img[25:35, 5:40] = True
    return comcore.Mask(img, resolution=0.005)


def synthetic_motions(
    mask: comcore.Mask, actions: np.ndarray, com, mu: float = 0.5, gain: float = 0.01
):
    """Toy physics: Voting-Theorem sense, magnitude growing with the lever arm."""
    con = comcore.geometry.contacts(mask, actions)
    direction = actions[:, 2:] - actions[:, :2]
    sense = np.array(
        [
            comcore.vt.predicted_sense(com, con.point[i], con.normal[i], direction[i], mu)
            for i in range(len(actions))
        ]
    )
    lever = np.abs(comcore.geometry.signed_line_distance([com], actions)[0])
    unit = direction / np.hypot(*direction.T)[:, None]
    return np.column_stack([sense * gain * lever, 12 * unit[:, 0], 12 * unit[:, 1]])


@pytest.fixture
def dask_scheduler_address():
    """The address of a one-worker, in-process Dask cluster started for the test.

    Its HTTP server binds a free port (``":0"``): with the default (8787), two xdist workers
    starting clusters at once collide, and distributed's "port in use" warning is an error here.
    """
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:
        yield cluster.scheduler_address


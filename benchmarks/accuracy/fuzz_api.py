"""Fuzz comcore's public API with odd arguments, one at a time, and count what each call does.

Run: ``python benchmarks/accuracy/fuzz_api.py [--seed 0] [--n 0] [--timeout 10]
[--workers 2] [--memory-gb 4] [--examples 3] [--json rows.json]``;
``--replay ID`` runs one case in this process (under the same limits) and prints its
traceback and its row;
``--targets toy`` runs the harness's own toy functions (the tests' known cases).

Each target is a public callable with a valid baseline call (a 20 x 20 pixel square, four
pushes and their motions, cheap options such as ``model=None``). A case calls it with one
argument replaced by a value of that argument's kind from the catalogue below (NaN, inf,
-0.0, huge, tiny, wrong types, wrong shapes and dtypes, odd masks ...), so each call tests
one thing. Every catalogue value carries a label: ``must_refuse`` (no meaning the argument
could have: a NaN resolution, an all-False mask for an estimator) or ``may_accept`` (odd
but legitimate: -0.0 as an angle, a push that misses the object, a ring mask for a contact
test). The cases are all (target, argument, value) triples in a fixed order, permuted by
``--seed``, after one baseline call per target; the first ``--n`` are run. A case's values
that are drawn at random use a generator seeded by (seed, case id), so the input set is a
pure function of ``--seed`` and ``--n`` (and of which extras are installed: the simulator's
and the ellipsoid's targets are left out, saying so, where their packages do not import), and
case ``ID`` is the same for every ``--n``.

Each call runs in a forked child (``--workers`` at a time) under an address-space limit
(``--memory-gb``, RLIMIT_AS, so a huge allocation is a MemoryError rather than the machine's
memory) and a wall-clock limit (``--timeout`` seconds). The classes:

* ``refused_clearly``: a TypeError, ValueError or ComcoreError whose message names the
  mutated argument as a whole word, singular or plural (its name; an alias the target
  declares, such as ``StopRule`` for ``stop``; "object" for a mask, as comcore's messages
  call it), raised by comcore rather than from inside numpy or scipy (the innermost frame).
* ``unclear_error``: any other exception (IndexError, ZeroDivisionError, MemoryError, a
  RuntimeError ...), or a TypeError/ValueError that does not name the argument or comes
  from inside numpy/scipy (a broadcast error, "could not convert string to float").
* ``silent``: the call returned although the value is ``must_refuse``; or it returned
  (whatever the label) a NaN/inf somewhere in its result (the path is kept; a target
  may declare a path where inf is documented, ``check_mu``'s open upper bound), or an answer
  the target's own check finds wrong (``sample_pushes`` returning pushes that miss the
  mask, an estimate outside the mask's box).
* ``accepted``: the baseline or a ``may_accept`` value returned a finite answer.
* ``hang``: past ``--timeout``; ``crash``: the child died without an answer (a signal,
  the kernel's OOM killer).
* ``baseline_failed``: the unmutated call raised (a harness bug; there should be none).
* ``harness_error``: the catalogue could not build the value (a harness bug).

Besides its class, a row says whether the call changed one of its input arrays or lists
in place (``mutated``: pickled before and after; generators and callables are not compared).
The measured counts, and why they are not comparable with an earlier uncommitted pass:
docs/results/robustness.md.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one thread per child: the pool is the parallelism

import argparse  # noqa: E402
import inspect  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import multiprocessing as mp  # noqa: E402
import multiprocessing.connection as mpc  # noqa: E402
import pickle  # noqa: E402
import re  # noqa: E402
import resource  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import traceback  # noqa: E402
import warnings  # noqa: E402
from collections import Counter, defaultdict  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import dataclass, field, fields, is_dataclass  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

import comcore  # noqa: E402
from comcore import checks, conventions, geometry, vt  # noqa: E402

R = "must_refuse"
A = "may_accept"
VALID = "valid"
CLASSES = (
    "refused_clearly",
    "unclear_error",
    "silent",
    "accepted",
    "hang",
    "crash",
    "baseline_failed",
    "harness_error",
)

# ---------------------------------------------------------------------------------------
# The catalogue: odd values per kind, each a (label, factory, verdict). A factory takes
# (rng, base): the case's generator and the argument's baseline value.


@dataclass(frozen=True)
class Odd:
    """One catalogue value: its label, how to build it, and whether it must be refused."""

    label: str
    make: Callable[[np.random.Generator, Any], Any]
    verdict: str


def _const(value):
    return lambda rng, base: value


def _f(label, make, verdict):  # a value built per case (from the generator or the baseline)
    return Odd(label, make, verdict)


def _c(label, value, verdict):  # a constant value
    return Odd(label, _const(value), verdict)


WRONG_TYPES = (
    _c("str", "abc", R),
    _c("dict", {}, R),
    _c("list_of_str", ["a", "b"], R),
    _f("object", lambda rng, base: object(), R),
)
NONE_R = (_c("none", None, R),)
NONE_A = (_c("none", None, A),)
SCALAR_TYPES = (
    _c("nan", math.nan, R),
    _c("inf", math.inf, R),
    _c("-inf", -math.inf, R),
    _c("numeric_str", "0.5", R),
    _c("bool", True, R),
    _c("complex", 1 + 1j, R),
    _c("array_2", np.array([1.0, 2.0]), R),
    _c("empty_array", np.array([]), R),
    _f("numpy_float32", lambda rng, base: np.float32(base), A),
    *WRONG_TYPES,
)
POSITIVE = (  # a positive number with no natural bound (a scale, a tolerance)
    *SCALAR_TYPES,
    _c("zero", 0.0, R),
    _c("-0.0", -0.0, R),
    _c("negative", -1.0, R),
    _c("huge", 1e300, A),
    _c("2**63", 2**63, A),
    _c("tiny", 5e-324, A),
    _f("baseline_x2", lambda rng, base: 2 * base, A),
    _f("random_scale", lambda rng, base: float(base * rng.uniform(0.5, 2.0)), A),
)
LENGTH = (  # a length in metres: a radius, a tolerance (5e-324 may mean "exactly")
    *SCALAR_TYPES,
    _c("zero", 0.0, R),
    _c("-0.0", -0.0, R),
    _c("negative", -0.01, R),
    _c("huge", 1e300, R),
    _c("2**63", 2**63, R),
    _c("tiny", 5e-324, R),
    _f("baseline_x2", lambda rng, base: 2 * base, A),
    _f("random_scale", lambda rng, base: float(base * rng.uniform(0.5, 2.0)), A),
)
LENGTH_STRICT = LENGTH  # a resolution or a push's travel: 5e-324 m is no camera and no push
LENGTH = tuple(Odd(o.label, o.make, A) if o.label == "tiny" else o for o in LENGTH_STRICT)
NONNEG_LENGTH = tuple(Odd(o.label, o.make, A) if o.label in ("zero", "-0.0") else o for o in LENGTH)
NONNEG = tuple(Odd(o.label, o.make, A) if o.label in ("zero", "-0.0") else o for o in POSITIVE)
PROBABILITY = (
    *SCALAR_TYPES,
    _c("zero", 0.0, A),
    _c("one", 1.0, A),
    _c("negative", -0.1, R),
    _c("above_one", 1.5, R),
    _c("huge", 1e300, R),
    _c("tiny", 5e-324, A),
    _f("random_in_0_1", lambda rng, base: float(rng.uniform(0.05, 0.95)), A),
)
COUNT = (  # a whole number >= 1
    *SCALAR_TYPES,
    _c("zero", 0, R),
    _c("negative", -1, R),
    _c("fraction", 2.5, R),
    _c("integral_float", 3.0, A),
    _c("numpy_int", np.int64(3), A),
    _c("10**12", 10**12, R),
    _c("2**63", 2**63, R),
    _c("huge_float", 1e300, R),
    _f("random_small", lambda rng, base: int(rng.integers(1, 6)), A),
)
ANGLE = (  # radians, any finite value
    *SCALAR_TYPES,
    _c("zero", 0.0, A),
    _c("-0.0", -0.0, A),
    _c("negative", -0.3, A),
    _c("ten_rad", 10.0, A),
    _c("huge", 1e300, R),
    _c("tiny", 5e-324, A),
    _f("random_angle", lambda rng, base: float(rng.uniform(-3, 3)), A),
)
COORD = (  # a pixel coordinate
    *SCALAR_TYPES,
    _c("zero", 0.0, A),
    _c("-0.0", -0.0, A),
    _c("negative", -5.0, A),
    _c("huge", 1e300, R),
    _c("tiny", 5e-324, A),
    _f("random_coord", lambda rng, base: float(rng.uniform(-10, 40)), A),
)
RNG = (
    _c("none", None, A),
    _c("zero", 0, A),
    _f("generator", lambda rng, base: np.random.default_rng(int(rng.integers(1000))), A),
    _c("negative", -1, R),
    _c("fraction", 1.5, R),
    _c("nan", math.nan, R),
    _c("2**64", 2**64, A),
    *WRONG_TYPES,
)
BOOL = (
    _c("true", True, A),
    _c("false", False, A),
    _c("numpy_bool", np.bool_(True), A),
    _c("int_one", 1, A),
    _c("str_no", "no", R),
    _c("nan", math.nan, R),
    _c("two", 2, R),
    _c("dict", {}, R),
    _c("none", None, R),
)


def str_option(valid: tuple[str, ...], optional: bool = False) -> tuple[Odd, ...]:
    """Odd values of an option that takes one of ``valid``."""
    return (
        _c("bogus", "bogus", R),
        _c("empty_str", "", R),
        _c("upper", valid[0].upper(), A if valid[0].upper() == valid[0] else R),
        _c("int", 1, R),
        _c("list", list(valid[:1]), R),
        _c("none", None, A if optional else R),
        *(_c(f"valid_{v}", v, A) for v in valid),
    )


def _points_odd(width: int) -> tuple[Odd, ...]:
    """Odd values of an (n, width) float array (points, actions, motions)."""

    def with_value(value):
        def make(rng, base):
            arr = np.array(base, float, copy=True).reshape(-1, width)
            arr[int(rng.integers(len(arr))), int(rng.integers(width))] = value
            return arr

        return make

    return (
        _f("nan_inside", with_value(math.nan), R),
        _f("inf_inside", with_value(math.inf), R),
        _f("huge_inside", with_value(1e300), R),
        _f("wrong_width", lambda rng, base: np.zeros((3, width + 1)), R),
        _f("three_d", lambda rng, base: np.zeros((2, 3, width)), R),
        _f(
            "transposed", lambda rng, base: np.array(base, float).reshape(-1, width)[:1].T.copy(), R
        ),
        _f(
            "object_dtype",
            lambda rng, base: np.array(base, float).reshape(-1, width).astype(object),
            A,
        ),
        _f(
            "complex", lambda rng, base: np.array(base, float).reshape(-1, width).astype(complex), R
        ),
        _f("int_dtype", lambda rng, base: np.round(np.array(base, float)).astype(np.int64), A),
        _f("as_lists", lambda rng, base: np.array(base, float).tolist(), A),
        _c("scalar", 1.0, R),
        _c("list_of_str_rows", [["a"] * width], R),
        *NONE_R,
        *WRONG_TYPES,
    )


POINT = (  # one (x, y)
    _c("nan_inside", (math.nan, 1.0), R),
    _c("inf_inside", (1.0, math.inf), R),
    _c("huge", (1e300, 1.0), R),
    _c("three_values", (1.0, 2.0, 3.0), R),
    _c("one_value", (1.0,), R),
    _c("empty", (), R),
    _c("complex", np.array([1 + 1j, 2.0]), R),
    _c("as_row", np.array([[10.0, 10.0]]), A),
    _f("random_point", lambda rng, base: tuple(rng.uniform(0, 28, 2)), A),
    _c("scalar", 1.0, R),
    *NONE_R,
    *WRONG_TYPES,
)
POINTS = (
    *_points_odd(2),
    _f("empty_rows", lambda rng, base: np.zeros((0, 2)), A),
    _f("random_points", lambda rng, base: rng.uniform(0, 28, (5, 2)), A),
)
ACTIONS = (
    *_points_odd(4),
    _f("empty_rows", lambda rng, base: np.zeros((0, 4)), A),
    _f("zero_length", lambda rng, base: np.array([[5.0, 5.0, 5.0, 5.0], *list(base)[1:]]), R),
    _f(
        "misses_the_object", lambda rng, base: np.array([[0.0, 1.0, 30.0, 1.0], *list(base)[1:]]), A
    ),
    _f("one_push_1d", lambda rng, base: np.array(base[0], float), A),
)
ONE_ACTION = (
    _c("nan_inside", (math.nan, 13.0, 30.0, 13.0), R),
    _c("inf_inside", (0.0, math.inf, 30.0, 13.0), R),
    _c("huge", (0.0, 13.0, 1e300, 13.0), R),
    _c("zero_length", (5.0, 5.0, 5.0, 5.0), R),
    _c("three_values", (0.0, 13.0, 30.0), R),
    _c("two_pushes", np.array([[0, 13, 30, 13], [13, 0, 13, 30]], float), R),
    _c("misses_the_object", (0.0, 1.0, 30.0, 1.0), A),
    _c("complex", np.array([0, 13, 30, 13], complex), R),
    _f(
        "random_push",
        lambda rng, base: (0.0, float(rng.uniform(5, 23)), 30.0, float(rng.uniform(5, 23))),
        A,
    ),
    *NONE_R,
    *WRONG_TYPES,
)
MOTIONS = (
    *_points_odd(3),
    _f("one_too_few", lambda rng, base: np.array(base, float)[:-1], R),
    _f("one_too_many", lambda rng, base: np.vstack([base, base[:1]]), R),
    _f("empty_rows", lambda rng, base: np.zeros((0, 3)), R),
    _f("ten_rad", lambda rng, base: np.array(base, float) * [50, 1, 1], A),
    _f("no_motion", lambda rng, base: np.zeros_like(np.array(base, float)), A),
)
ONE_MOTION = (
    _c("nan_inside", (math.nan, 0.0, 0.0), R),
    _c("inf_inside", (0.1, math.inf, 0.0), R),
    _c("huge", (1e300, 0.0, 0.0), R),
    _c("two_values", (0.1, 0.0), R),
    _c("four_values", (0.1, 0.0, 0.0, 0.0), R),
    _c("empty", (), R),
    _c("complex", np.array([0.1 + 1j, 0.0, 0.0]), R),
    _c("ten_rad", (10.0, 0.0, 0.0), A),
    _c("no_motion", (0.0, 0.0, 0.0), A),
    _c("-0.0", (-0.0, -0.0, -0.0), A),
    _f("random_motion", lambda rng, base: tuple(rng.uniform(-0.3, 0.3, 3)), A),
    *WRONG_TYPES,
)


def _square(n=20, pad=4):
    return np.pad(np.ones((n, n), bool), pad)


def _ring():
    yy, xx = np.mgrid[0:40, 0:40]
    r = np.hypot(xx - 19.5, yy - 19.5)
    return (r < 15) & (r > 8)


def _two_blobs():
    img = np.zeros((30, 50), bool)
    img[5:25, 3:20] = True
    img[5:25, 30:47] = True
    return img


def _line():
    img = np.zeros((20, 40), bool)
    img[10, 5:35] = True
    return img


def _one_pixel():
    img = np.zeros((10, 10), bool)
    img[5, 5] = True
    return img


def _checkerboard():
    return (np.indices((20, 20)).sum(0) % 2).astype(bool)


def _small_hole():
    img = _square(30, 4)
    img[18, 18] = False
    return img


def _random_polygon(rng, size=40):
    n = int(rng.integers(3, 9))
    angles = np.sort(rng.uniform(0, 2 * np.pi, n))
    radius = rng.uniform(8, 16, n)
    verts = np.column_stack(
        [size / 2 + radius * np.cos(angles), size / 2 + radius * np.sin(angles)]
    )
    img = geometry.rasterise_polygon(verts, (size, size))
    return img if img.sum() > 30 else _square()


def _huge_view():
    return np.broadcast_to(np.True_, (100_000, 100_000))


def _mask(make):
    return lambda rng, base: comcore.Mask(make())


def mask_odd(one_object: bool) -> tuple[Odd, ...]:
    """Odd masks: ``one_object`` when the callee needs one solid object (the estimators)."""
    need = R if one_object else A
    return (
        _f("all_false_array", lambda rng, base: np.zeros((20, 20), bool), R),
        _f("one_pixel", _mask(_one_pixel), need),
        _f("line", _mask(_line), need),
        _f("ring", _mask(_ring), need),
        _f("two_blobs", _mask(_two_blobs), need),
        _f("checkerboard", _mask(_checkerboard), need),
        _f("1x1", _mask(lambda: np.ones((1, 1), bool)), need),
        _f("5000x1", _mask(lambda: np.ones((5000, 1), bool)), need),
        _f("small_hole", _mask(_small_hole), A),
        _f("raw_bool_array", lambda rng, base: _square(), A),
        _f("other_resolution", lambda rng, base: comcore.Mask(_square(), resolution=0.001), A),
        _f(
            "wide_frame",
            lambda rng, base: comcore.Mask(np.pad(_square(), ((0, 400), (0, 700)))),
            A,
        ),
        _f("random_polygon", lambda rng, base: comcore.Mask(_random_polygon(rng)), A),
        _f("three_d_array", lambda rng, base: np.ones((4, 4, 4), bool), R),
        _c("int", 3, R),
        *NONE_R,
        *WRONG_TYPES,
    )


MASK_DATA = (  # what Mask(data) is given
    _f("all_false", lambda rng, base: np.zeros((20, 20), bool), R),
    _f("1x1", lambda rng, base: np.ones((1, 1), bool), A),
    _f("5000x1", lambda rng, base: np.ones((5000, 1), bool), A),
    _f("one_pixel", lambda rng, base: _one_pixel(), A),
    _f("ring", lambda rng, base: _ring(), A),
    _f("three_d", lambda rng, base: np.ones((4, 4, 4), bool), R),
    _f("one_d", lambda rng, base: np.ones(10, bool), R),
    _f("empty", lambda rng, base: np.zeros((0, 0), bool), R),
    _f("object_dtype", lambda rng, base: _square().astype(object), A),
    _f("complex", lambda rng, base: _square().astype(complex), R),
    _f("float_with_nan", lambda rng, base: np.where(_square(), np.nan, 0.0), R),
    _f("float_0_1", lambda rng, base: _square().astype(float), A),
    _f("uint8_0_255", lambda rng, base: _square().astype(np.uint8) * 255, A),
    _f("int_2", lambda rng, base: _square().astype(int) * 2, A),
    _f("lists", lambda rng, base: _square().tolist(), A),
    _f("huge_view", lambda rng, base: _huge_view(), R),
    _f("random_polygon", lambda rng, base: _random_polygon(rng), A),
    _c("scalar_true", True, R),
    *NONE_R,
    *WRONG_TYPES,
)


def _image():
    img = np.full((40, 60), 200, np.uint8)
    img[10:30, 15:45] = 30
    return img


IMAGE = (  # a camera image for mask_from_image
    _f("constant", lambda rng, base: np.full((40, 60), 200, np.uint8), R),
    _f("rgb", lambda rng, base: np.repeat(_image()[..., None], 3, axis=2), A),
    _f("float_0_1", lambda rng, base: _image() / 255.0, A),
    _f("bool", lambda rng, base: _image() < 100, A),
    _f("four_d", lambda rng, base: np.zeros((2, 40, 60, 3), np.uint8), R),
    _f("one_d", lambda rng, base: np.zeros(60, np.uint8), R),
    _f("empty", lambda rng, base: np.zeros((0, 0), np.uint8), R),
    _f("float_nan", lambda rng, base: np.where(_image() < 100, np.nan, 0.8), R),
    _f("float_inf", lambda rng, base: np.where(_image() < 100, np.inf, 0.8), R),
    _f("object_dtype", lambda rng, base: _image().astype(object), A),
    _f("complex", lambda rng, base: _image().astype(complex), R),
    _f("1x1", lambda rng, base: np.zeros((1, 1), np.uint8), R),
    _f("5000x1", lambda rng, base: np.zeros((5000, 1), np.uint8), R),
    _f("huge_view", lambda rng, base: np.broadcast_to(np.uint8(9), (100_000, 100_000)), R),
    _f("noise", lambda rng, base: rng.integers(0, 256, (40, 60)).astype(np.uint8), A),
    *NONE_R,
    *WRONG_TYPES,
)
SQUARE_M = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
OUTLINE = (  # a polygon in metres
    _c("two_points", SQUARE_M[:2], R),
    _c("collinear", [(0, 0), (0.01, 0), (0.02, 0)], R),
    _c("bowtie", [(0, 0), (0.04, 0.04), (0.04, 0), (0, 0.04)], R),
    _c("nan_inside", [(math.nan, 0), *SQUARE_M[1:]], R),
    _c("inf_inside", [(math.inf, 0), *SQUARE_M[1:]], R),
    _c("huge", [(1e300 * x, 1e300 * y) for x, y in SQUARE_M], R),
    _c("tiny", [(1e-9 * x, 1e-9 * y) for x, y in SQUARE_M], R),
    _c("millimetres_as_metres", [(1000 * x, 1000 * y) for x, y in SQUARE_M], R),
    _c("clockwise", SQUARE_M[::-1], A),
    _c("closed", SQUARE_M + SQUARE_M[:1], A),
    _c("three_columns", [(x, y, 0.0) for x, y in SQUARE_M], R),
    _c("three_d", np.zeros((2, 4, 2)), R),
    _c("empty", np.zeros((0, 2)), R),
    _f(
        "random_polygon",
        lambda rng, base: [
            (0.03 * math.cos(a), 0.03 * math.sin(a)) for a in np.sort(rng.uniform(0, 2 * np.pi, 6))
        ],
        A,
    ),
    *NONE_R,
    *WRONG_TYPES,
)


def _poses():
    t = np.linspace(0.0, 1.0, 101)
    pusher = np.column_stack([t, np.full_like(t, 0.01), -0.034 + 0.04 * t, 0 * t])
    moving = np.clip(t - 0.1, 0, None)
    obj = np.column_stack([t, 0 * t, 0.04 * moving, 0.2 * moving])
    return obj, pusher


def _poses_with(change):
    def make(rng, base):
        obj, pusher = _poses()
        return [change(obj.copy(), pusher.copy())]

    return make


def _set(arr, idx, value):
    arr[idx] = value
    return arr


POSE_PUSHES = (  # recording_from_poses' pushes: [(object poses, pusher poses)]
    _c("empty_list", [], A),
    _f("nan_in_object", _poses_with(lambda o, p: (_set(o, (50, 2), math.nan), p)), R),
    _f("inf_in_pusher", _poses_with(lambda o, p: (o, _set(p, (50, 2), math.inf))), R),
    _f("time_backwards", _poses_with(lambda o, p: (o[::-1].copy(), p[::-1].copy())), R),
    _f("object_three_columns", _poses_with(lambda o, p: (o[:, :3].copy(), p)), R),
    _f("pusher_never_touches", _poses_with(lambda o, p: (o, _set(p, (slice(None), 3), 0.5))), A),
    _f("one_sample", _poses_with(lambda o, p: (o[:1].copy(), p[:1].copy())), R),
    _f("three_arrays", lambda rng, base: [(*_poses(), _poses()[0])], R),
    _f("huge_times", _poses_with(lambda o, p: (_set(o, (slice(None), 0), o[:, 0] * 1e300), p)), R),
    *NONE_R,
    *WRONG_TYPES,
)
MU = (
    _c("none", None, A),
    _c("one_value", 0.3, A),
    _c("interval", (0.2, 0.5), A),
    _c("reversed_interval", (0.5, 0.2), R),
    _c("negative", -0.1, R),
    _c("zero", 0.0, A),
    _c("nan", math.nan, R),
    _c("inf", math.inf, R),
    _c("huge", 1e300, R),
    _c("three_values", (0.1, 0.2, 0.3), R),
    _c("bool", True, R),
    *WRONG_TYPES,
)
PAIR_POSITIVE = (  # a (low, high) pair of positive scales
    _c("nan_inside", (math.nan, 0.1), R),
    _c("inf_inside", (0.01, math.inf), R),
    _c("negative", (-0.01, 0.1), R),
    _c("one_value", (0.01,), R),
    _c("three_values", (0.01, 0.1, 1.0), R),
    _c("scalar", 0.01, A),
    _c("zeros", (0.0, 0.0), R),
    _c("huge", (1e300, 1e300), R),
    *NONE_R,
    *WRONG_TYPES,
)


def group_odd(cls, other, valid) -> tuple[Odd, ...]:
    """Odd values of an option group: a dict, a string, the wrong group."""
    return (
        _c("none", None, A),
        _f("valid_group", lambda rng, base: valid(), A),
        _c("dict", {"max_pushes": 3}, R),
        _f("wrong_group", lambda rng, base: other(), R),
        _f("the_class", lambda rng, base: cls, R),
        _c("str", "abc", R),
        _c("int", 3, R),
    )


MODEL = (
    _c("none", None, A),
    _c("str", "limit-surface", R),
    _f("object", lambda rng, base: object(), R),
    _c("int", 1, R),
    _f("limit_surface_model", lambda rng, base: comcore.LimitSurfaceModel(pusher_radius=0.004), A),
    _f("a_function", lambda rng, base: lambda mask, actions, priors=(): None, R),
)


def _push_returning(value):
    return lambda rng, base: lambda action: value


PUSH = (  # estimate_active's push callable
    _f("returns_nan", _push_returning((math.nan, 0.0, 0.0)), R),
    _f("returns_inf", _push_returning((0.1, math.inf, 0.0)), R),
    _f("returns_str", _push_returning("abc"), R),
    _f("returns_two_values", _push_returning((0.1, 0.0)), R),
    _f("returns_huge", _push_returning((1e300, 0.0, 0.0)), R),
    _f("returns_no_motion", _push_returning((0.0, 0.0, 0.0)), A),
    _c("not_callable", 5, R),
    *NONE_R,
    _c("str", "abc", R),
)
SHAPE = (  # an image shape (rows, columns)
    _c("zeros", (0, 0), R),
    _c("negative", (-1, 5), R),
    _c("huge", (10**6, 10**6), R),
    _c("fraction", (2.5, 3), R),
    _c("one_value", (5,), R),
    _c("three_values", (5, 5, 5), A),
    _c("nan", (math.nan, 5), R),
    _c("one_by_one", (1, 1), A),
    *NONE_R,
    *WRONG_TYPES,
)
NAME = (_c("int", 123, A), _c("none", None, A), _c("empty", "", A), _c("long", "x" * 1000, A))
GOAL = (
    _c("dict", {"displacement": (0.03, 0.0)}, R),
    _c("tuple", (0.03, 0.0), R),
    _f("far_away", lambda rng, base: comcore.Goal(displacement=(100.0, 0.0)), R),
    _f("turn_only", lambda rng, base: comcore.Goal(orientation=0.5), A),
    _f("position_goal", lambda rng, base: comcore.Goal(position=(0.1, 0.1)), A),
    *NONE_R,
    _c("str", "abc", R),
)
SENSE = (
    _c("zero", 0, A),
    _c("two", 2, R),
    _c("nan", math.nan, R),
    _c("negative_one", -1, A),
    _c("array_of_two", np.array([1, -1]), A),
    *NONE_R,
    *WRONG_TYPES,
)
PRIOR = (  # a prior over the mask's pixels (or None)
    _c("none", None, A),
    _f("uniform", lambda rng, base: np.ones((28, 28)), A),
    _f("all_zero", lambda rng, base: np.zeros((28, 28)), R),
    _f("negative", lambda rng, base: -np.ones((28, 28)), R),
    _f("nan", lambda rng, base: np.full((28, 28), math.nan), R),
    _f("wrong_shape", lambda rng, base: np.ones((5, 5)), R),
    *WRONG_TYPES,
)

ROI = (  # mask_from_image's region of interest
    _c("none", None, A),
    _c("nan", (math.nan, 0, 10, 10), R),
    _c("negative", (-5, -5, -1, -1), R),
    _c("empty", (10, 10, 10, 10), R),
    _c("huge", (0, 0, 10**9, 10**9), A),
    _c("two_values", (1, 2), R),
    *WRONG_TYPES,
)

CATALOGUE: dict[str, tuple[Odd, ...]] = {
    "positive": POSITIVE,
    "nonneg": NONNEG,
    "length": LENGTH,
    "length_strict": LENGTH_STRICT,
    "nonneg_length": NONNEG_LENGTH,
    "probability": PROBABILITY,
    "count": COUNT,
    "angle": ANGLE,
    "coord": COORD,
    "rng": RNG,
    "bool": BOOL,
    "point": POINT,
    "points": POINTS,
    "actions": ACTIONS,
    "action": ONE_ACTION,
    "motions": MOTIONS,
    "motion": ONE_MOTION,
    "object_mask": mask_odd(one_object=True),
    "any_mask": mask_odd(one_object=False),
    "mask_data": MASK_DATA,
    "image": IMAGE,
    "outline": OUTLINE,
    "pose_pushes": POSE_PUSHES,
    "mu": MU,
    "pair": PAIR_POSITIVE,
    "model": MODEL,
    "push": PUSH,
    "shape": SHAPE,
    "name": NAME,
    "goal": GOAL,
    "sense": SENSE,
    "prior": PRIOR,
}

# ---------------------------------------------------------------------------------------
# The targets: a callable, its baseline arguments (built fresh in each child) and a kind
# per argument fuzzed.


# comcore's messages call a mask "the object" ("actions must hit the object")
KIND_ALIASES = {"object_mask": ("object",), "any_mask": ("object",)}


@dataclass
class Arg:
    """One argument fuzzed: its kind, its baseline, the words that name it in a message."""

    name: str
    kind: str | tuple[Odd, ...]
    aliases: tuple[str, ...] = ()
    verdicts: dict[str, str] = field(default_factory=dict)  # overrides by label
    compare: bool = True  # pickled before and after the call (False: generators, callables)
    base: Callable[[], Any] | None = None  # the baseline where the baseline call omits it

    def names(self) -> tuple[str, ...]:
        """The words that name this argument in a message: its own, its aliases, its kind's."""
        kind = self.kind if isinstance(self.kind, str) else ""
        return (self.name, *self.aliases, *KIND_ALIASES.get(kind, ()))

    def catalogue(self) -> tuple[Odd, ...]:
        """This argument's odd values, with its verdict overrides applied."""
        odds = CATALOGUE[self.kind] if isinstance(self.kind, str) else self.kind
        return tuple(Odd(o.label, o.make, self.verdicts.get(o.label, o.verdict)) for o in odds)


@dataclass
class Target:
    """A public callable under test: ``call(**kwargs)`` with ``baseline()``'s arguments."""

    name: str
    call: Callable[..., Any]
    baseline: Callable[[], dict]
    args: tuple[Arg, ...]
    verify: Callable[[Any, dict], str | None] | None = None
    nonfinite_ok: tuple[str, ...] = ()  # result paths where inf is documented (no upper bound)


def _mask0():
    return comcore.Mask(_square())


ACTIONS0 = [(0, 13, 30, 13), (13, 0, 13, 30), (0, 8, 30, 8), (8, 0, 8, 30)]
MOTIONS0 = [(0.2, 3, 0), (-0.2, 0, 3), (-0.3, 3, 0), (0.3, 0, 3)]


def _data(kwargs):
    mask = kwargs.get("mask")
    return mask.data if isinstance(mask, comcore.Mask) else np.asarray(mask, bool)


def _verify_estimate(result, kwargs):
    """An estimate's CoM inside the mask's box (a pixel's slack)."""
    try:
        data = _data(kwargs)
        rows, cols = np.nonzero(data)
        x, y = result.com
    except Exception:
        return None
    if not (cols.min() - 1 <= x <= cols.max() + 1 and rows.min() - 1 <= y <= rows.max() + 1):
        return f"com {result.com} outside the mask's box"
    return None


def _verify_pushes(result, kwargs):
    """``sample_pushes``: n pushes, each of which meets the mask."""
    try:
        mask = (
            kwargs["mask"]
            if isinstance(kwargs["mask"], comcore.Mask)
            else comcore.Mask(kwargs["mask"])
        )
        hit = geometry.contacts(mask, result).hit
    except Exception:
        return None
    n = kwargs.get("n")
    if isinstance(n, (int, np.integer)) and len(result) != n:
        return f"{len(result)} pushes for n={n}"
    if not np.all(hit):
        return f"{int(np.sum(~np.asarray(hit)))} of {len(result)} pushes miss the mask"
    return None


def _session(model=None, **kw):
    session = comcore.ActiveSession(_mask0(), model=model, rng=0, **kw)
    session.next_push()
    return session


def _observe(session=None, **kwargs):
    session.observe(**kwargs)
    return session.estimate()


def _goal_session():
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 40))
    goal = comcore.Goal(displacement=(0.03, 0.0))
    session = comcore.GoalSession(
        mask, goal=goal, travel=0.02, model=None, rng=0
    )
    session.next_push()
    return session


def _goal_observe(session=None, **kwargs):
    session.observe(**kwargs)
    return session.status


def _shifted_mask():
    return comcore.Mask(np.roll(_square(), 2, axis=1))


def _sim():
    import simulators

    return simulators.PushSimulator.from_polygon([(0, 0), (0.08, 0), (0.08, 0.06), (0, 0.06)])


def _from_polygon(**kwargs):
    import simulators

    return simulators.PushSimulator.from_polygon(**kwargs)


def _ellipsoid(**kwargs):
    from predictors import EllipsoidPredictor

    return EllipsoidPredictor(**kwargs)


def _ellipsoid_predict(**kwargs):
    from predictors import EllipsoidPredictor

    return EllipsoidPredictor(com=(13.5, 13.5), mu_contact=0.3).predict(**kwargs)


def _est_kwargs():
    return dict(mask=_mask0(), actions=list(ACTIONS0), motions=list(MOTIONS0))


STOP = (comcore.StopRule, lambda: comcore.PushChoice(), lambda: comcore.StopRule(max_pushes=3))
LIKELIHOOD = (
    comcore.Likelihood,
    lambda: comcore.StopRule(),
    lambda: comcore.Likelihood(flip_prob=0.1),
)
CHOICE = (
    comcore.PushChoice,
    lambda: comcore.Likelihood(),
    lambda: comcore.PushChoice(n_candidates=20),
)

MASK_ARG = Arg("mask", "object_mask")
# the frame conventions and the validators are arithmetic on finite numbers: 1e300 is one
FINITE_OK = {"huge": A, "huge_inside": A}
ACTIONS_ARG = Arg("actions", "actions", verdicts={"misses_the_object": A})
MOTIONS_ARG = Arg("motions", "motions")


def api_targets() -> list[Target]:
    """comcore's public callables, with their baseline calls."""
    T = Target
    targets = [
        T(
            "Mask",
            comcore.Mask,
            lambda: dict(data=_square(), resolution=0.0025),
            (Arg("data", "mask_data", aliases=("mask",)), Arg("resolution", "length_strict")),
        ),
        T(
            "Action",
            comcore.Action,
            lambda: dict(sx=0.0, sy=13.0, ex=30.0, ey=13.0),
            (Arg("sx", "coord"), Arg("ey", "coord")),
        ),
        T(
            "Motion",
            comcore.Motion,
            lambda: dict(theta=0.1, tx=1.0, ty=0.0),
            (Arg("theta", "angle"), Arg("tx", "coord")),
        ),
        T(
            "Estimate",
            comcore.Estimate,
            lambda: dict(com=(13.5, 13.5), com_m=(0.03375, 0.03375), region=_square()),
            (
                Arg("com", "point"),
                Arg("region", "mask_data"),
                Arg("status", str_option(("ok", "unchecked"))),
            ),
        ),
        T(
            "estimate_heatmap",
            comcore.estimate_heatmap,
            _est_kwargs,
            (
                MASK_ARG,
                ACTIONS_ARG,
                MOTIONS_ARG,
                Arg("threshold", "probability"),
                Arg("length_scale", "positive"),
            ),
            verify=_verify_estimate,
        ),
        T(
            "estimate_progressive",
            comcore.estimate_progressive,
            _est_kwargs,
            (
                MASK_ARG,
                ACTIONS_ARG,
                MOTIONS_ARG,
                Arg("area_ratio", "probability"),
                Arg("band", "nonneg"),
                Arg("min_rotation", "angle", verdicts={"negative": R, "huge": R}),
                Arg("min_score", "probability"),
                Arg("selection", str_option(("equality", "area"))),
                Arg("mu", "mu"),
                Arg("pusher_radius", "nonneg_length"),
                Arg("target_radius", "length"),
            ),
            verify=_verify_estimate,
        ),
        T(
            "estimate_posterior",
            comcore.estimate_posterior,
            lambda: dict(_est_kwargs(), model=None, bootstrap=20),
            (
                MASK_ARG,
                ACTIONS_ARG,
                MOTIONS_ARG,
                Arg("credible", "probability", verdicts={"zero": R, "one": R}),
                Arg("bootstrap", "count", verdicts={"zero": A, "10**12": R}),
                Arg("rng", "rng", compare=False),
                Arg("theta_units", str_option(("auto", "rad", "deg"))),
                Arg("pusher_radius", "nonneg_length"),
                Arg("prior", "prior"),
                Arg("likelihood", group_odd(*LIKELIHOOD), aliases=("Likelihood",)),
                Arg("target_radius", "length"),
                Arg("model", "model"),
            ),
            verify=_verify_estimate,
        ),
        T(
            "estimate_posterior[limit-surface]",
            comcore.estimate_posterior,
            lambda: dict(_est_kwargs(), bootstrap=5),
            (MOTIONS_ARG, Arg("pusher_radius", "nonneg_length")),
            verify=_verify_estimate,
        ),
        T(
            "ActiveSession",
            comcore.ActiveSession,
            lambda: dict(mask=_mask0(), model=None, rng=0),
            (
                MASK_ARG,
                Arg(
                    "candidates",
                    "actions",
                    base=lambda: list(ACTIONS0),
                    verdicts={"none": A, "empty_rows": R, "misses_the_object": A},
                ),
                Arg("pusher_radius", "nonneg_length"),
                Arg("credible", "probability", verdicts={"zero": R, "one": R}),
                Arg("rng", "rng", compare=False),
                Arg("prior", "prior"),
                Arg("model", "model"),
                Arg("likelihood", group_odd(*LIKELIHOOD), aliases=("Likelihood",)),
                Arg("stop", group_odd(*STOP), aliases=("StopRule",)),
                Arg("choice", group_odd(*CHOICE), aliases=("PushChoice",)),
            ),
        ),
        T(
            "ActiveSession.observe",
            _observe,
            lambda: dict(session=_session(), motion=(0.1, 0.0, 0.0)),
            (
                Arg("motion", "motion"),
                Arg("failed", "bool", verdicts={"true": A}),
                Arg("reset", "bool"),
                Arg("executed", "action", verdicts={"none": A}),
            ),
            verify=_verify_estimate_session,
        ),
        T(
            "ActiveSession.observe[mask]",
            _observe,
            lambda: dict(session=_session(), mask=_shifted_mask()),
            (Arg("mask", "object_mask", verdicts={"other_resolution": R, "wide_frame": A}),),
        ),
        T(
            "ActiveSession.observe[limit-surface]",
            _observe,
            lambda: dict(
                session=_session(comcore.LimitSurfaceModel(pusher_radius=0.004)),
                motion=(0.1, 0.0, 0.0),
            ),
            (Arg("motion", "motion"),),
        ),
        T(
            "estimate_active",
            comcore.estimate_active,
            lambda: dict(
                mask=_mask0(),
                push=lambda action: (0.1, 0.0, 0.0),
                model=None,
                rng=0,
                stop=comcore.StopRule(max_pushes=3),
            ),
            (
                MASK_ARG,
                Arg("push", "push", compare=False, aliases=("motion",)),
                Arg(
                    "candidates",
                    "actions",
                    base=lambda: list(ACTIONS0),
                    verdicts={"none": A, "empty_rows": R},
                ),
                Arg("stop", group_odd(*STOP), aliases=("StopRule",)),
                Arg("choice", group_odd(*CHOICE), aliases=("PushChoice",)),
                Arg("rng", "rng", compare=False),
            ),
            verify=_verify_estimate,
        ),
        T(
            "sample_pushes",
            comcore.sample_pushes,
            lambda: dict(mask=_mask0(), n=10, rng=0),
            (
                Arg("mask", "any_mask"),
                Arg("n", "count", verdicts={"zero": A}),
                Arg("cone", "angle", verdicts={"negative": R, "ten_rad": R, "huge": R}),
                Arg("travel", "length_strict"),
                Arg("standoff", "nonneg_length"),
                Arg("clearance", "nonneg_length"),
                Arg("rng", "rng", compare=False),
            ),
            verify=_verify_pushes,
        ),
        T(
            "mask_from_outline",
            comcore.mask_from_outline,
            lambda: dict(outline=SQUARE_M),
            (
                Arg("outline", "outline"),
                Arg("resolution", "length_strict"),
                Arg("margin", "nonneg_length"),
            ),
        ),
        T(
            "mask_from_image",
            comcore.mask_from_image,
            lambda: dict(image=_image()),
            (
                Arg("image", "image"),
                Arg("threshold", "coord", verdicts={"negative": R}),
                Arg("object", str_option(("auto", "dark", "light"))),
                Arg("fill_holes", "bool"),
                Arg("resolution", "length_strict"),
                Arg("roi", ROI),
            ),
        ),
        T(
            "measure_motion",
            comcore.measure_motion,
            lambda: dict(before=_mask0(), after=_shifted_mask()),
            (Arg("before", "object_mask"), Arg("after", "object_mask"), Arg("near_theta", "angle")),
        ),
        T(
            "recording_from_poses",
            comcore.recording_from_poses,
            lambda: dict(
                outline=SQUARE_M, pushes=[_poses()], pusher_radius=0.004, travel=0.02, com=(0, 0)
            ),
            (
                Arg("outline", "outline"),
                Arg("pushes", "pose_pushes"),
                Arg("pusher_radius", "nonneg_length"),
                Arg("travel", "length_strict"),
                Arg("resolution", "length_strict"),
                Arg("com", "point", verdicts={"none": A, "huge": R}),
                Arg("contact_tolerance", "length"),
            ),
        ),
        T(
            "Likelihood",
            comcore.Likelihood,
            dict,
            (
                Arg("mu", "mu"),
                Arg("n_mu", "count"),
                Arg("flip_prob", "probability", verdicts={"one": R}),
                Arg("theta_tol", "nonneg"),
                Arg("theta_noise", "pair"),
                Arg("translation_error", "pair"),
                Arg("pusher_error", "nonneg_length"),
                Arg("motion_noise", "pair"),
                Arg("model_weight", "probability", verdicts={"numpy_float32": A}),
                Arg("systematic_error", "nonneg", verdicts={}),
            ),
        ),
        T(
            "StopRule",
            comcore.StopRule,
            dict,
            (
                Arg("max_pushes", "count"),
                Arg("min_pushes", "count", verdicts={"zero": A}),
                Arg("target_radius", "length"),
                Arg("min_information", "nonneg"),
            ),
        ),
        T(
            "PushChoice",
            comcore.PushChoice,
            dict,
            (
                Arg("selection", str_option(("sense", "information"))),
                Arg("n_candidates", "count"),
                Arg("cone", "angle", verdicts={"negative": R, "ten_rad": R}),
                Arg("travel", "length_strict"),
            ),
        ),
        T(
            "Goal",
            comcore.Goal,
            lambda: dict(displacement=(0.03, 0.0)),
            (
                Arg("displacement", "point", verdicts={"none": R}),
                Arg("orientation", "angle"),
                Arg("units", str_option(("m", "px"))),
                Arg("position_tolerance", "length"),
                Arg("orientation_tolerance", "positive"),
                Arg("max_turn", "positive"),
            ),
        ),
        T(
            "GoalSession",
            lambda **kw: comcore.GoalSession(**kw).next_push(),
            lambda: dict(
                mask=comcore.Mask(np.pad(np.ones((20, 20), bool), 40)),
                goal=comcore.Goal(displacement=(0.03, 0.0)),
                travel=0.02,
                model=None,
                rng=0,
            ),
            (
                Arg("mask", "object_mask", aliases=("view",), verdicts={"wide_frame": A}),
                Arg("goal", "goal"),
                Arg("pusher_radius", "nonneg_length"),
                Arg("max_pushes", "count"),
                Arg("travel", "length_strict"),
                Arg("learn", "bool"),
                Arg("n_particles", "count"),
                Arg("rng", "rng", compare=False),
            ),
        ),
        T(
            "GoalSession.observe",
            _goal_observe,
            lambda: dict(session=_goal_session(), motion=(0.0, 12.0, 0.0)),
            (Arg("motion", "motion"), Arg("out_of_view", "bool")),
        ),
        # comcore.conventions
        T(
            "conventions.apply_motion",
            conventions.apply_motion,
            lambda: dict(
                points=np.array([[1.0, 2.0], [3.0, 4.0]]),
                theta=0.1,
                translation=(1.0, 0.0),
                center=(0.0, 0.0),
            ),
            (
                Arg("points", "points", verdicts=FINITE_OK),
                Arg("theta", "angle", verdicts=FINITE_OK),
                Arg("translation", "point", verdicts=FINITE_OK),
                Arg("center", "point", verdicts=FINITE_OK),
            ),
        ),
        T(
            "conventions.ccw_cross",
            conventions.ccw_cross,
            lambda: dict(a=np.array([1.0, 0.0]), b=np.array([0.0, 1.0])),
            (Arg("a", "points", verdicts=FINITE_OK), Arg("b", "points", verdicts=FINITE_OK)),
        ),
        T(
            "conventions.check_plausible",
            conventions.check_plausible,
            lambda: dict(value=0.0025, name="resolution", kind="resolution"),
            (
                Arg("value", "positive", aliases=("resolution",)),
                Arg("kind", str_option(("resolution",))),
            ),
        ),
        T(
            "conventions.object_motion_from_camera",
            conventions.object_motion_from_camera,
            lambda: dict(motion=(0.1, 1.0, 0.0), pose_theta=0.2),
            (
                Arg("motion", "motion", verdicts=FINITE_OK),
                Arg("pose_theta", "angle", verdicts=FINITE_OK),
            ),
        ),
        T(
            "conventions.pixel_centres",
            conventions.pixel_centres,
            lambda: dict(image=_square()),
            (Arg("image", "mask_data", verdicts={"all_false": A, "int_2": R, "uint8_0_255": R}),),
        ),
        T(
            "conventions.quarter_turn_ccw",
            conventions.quarter_turn_ccw,
            lambda: dict(vectors=np.array([[1.0, 0.0]])),
            (Arg("vectors", "points", verdicts=FINITE_OK),),
        ),
        T(
            "conventions.rotate_vectors",
            conventions.rotate_vectors,
            lambda: dict(vectors=np.array([[1.0, 0.0]]), theta=0.3),
            (
                Arg("vectors", "points", verdicts=FINITE_OK),
                Arg("theta", "angle", verdicts=FINITE_OK),
            ),
        ),
        T(
            "conventions.rotation_matrix",
            conventions.rotation_matrix,
            lambda: dict(theta=0.3),
            (Arg("theta", "angle", verdicts=FINITE_OK),),
        ),
        T(
            "conventions.rotation_sense",
            conventions.rotation_sense,
            lambda: dict(theta=np.array([0.1, -0.1, 0.0])),
            (
                Arg("theta", "angle", verdicts={**FINITE_OK, "array_2": A, "empty_array": A}),
                Arg("tol", "nonneg"),
            ),
        ),
        T(
            "conventions.rotate_components",
            conventions.rotate_components,
            lambda: dict(
                x=np.array([1.0]), y=np.array([0.0]), cos=math.cos(0.3), sin=math.sin(0.3)
            ),
            (Arg("x", "coord", verdicts=FINITE_OK), Arg("cos", "coord", verdicts={"huge": R})),
        ),
        # comcore.checks
        T(
            "checks.check_actions",
            checks.check_actions,
            lambda: dict(actions=list(ACTIONS0)),
            (Arg("actions", "actions", verdicts=FINITE_OK), Arg("allow_empty", "bool")),
        ),
        T(
            "checks.check_mask",
            checks.check_mask,
            lambda: dict(mask=_mask0()),
            (Arg("mask", "any_mask", verdicts={"three_d_array": R}), Arg("name", "name")),
        ),
        T(
            "checks.check_motions",
            checks.check_motions,
            lambda: dict(motions=list(MOTIONS0), n=4),
            (
                Arg("motions", "motions", verdicts=FINITE_OK),
                Arg("n", "count", verdicts={"zero": A}),
            ),
        ),
        T(
            "checks.check_mu",
            checks.check_mu,
            lambda: dict(mu=0.3),
            (Arg("mu", "mu", verdicts={"none": A}),),
            nonfinite_ok=("result[1]",),  # (low, inf): no upper bound on the friction
        ),
        T(
            "checks.check_one_object",
            checks.check_one_object,
            lambda: dict(mask=_mask0()),
            (MASK_ARG,),
        ),
        T(
            "checks.check_point",
            checks.check_point,
            lambda: dict(value=(1.0, 2.0)),
            (Arg("value", "point", aliases=("point",), verdicts=FINITE_OK),),
        ),
        T(
            "checks.check_points",
            checks.check_points,
            lambda: dict(points=[(1.0, 2.0)]),
            (Arg("points", "points", verdicts=FINITE_OK),),
        ),
        T(
            "checks.check_positive",
            checks.check_positive,
            lambda: dict(value=0.5, name="x"),
            (Arg("value", "positive", aliases=("x",)), Arg("name", "name")),
        ),
        T(
            "checks.check_probability",
            checks.check_probability,
            lambda: dict(value=0.5, name="p"),
            (Arg("value", "probability", aliases=("p",)),),
        ),
        T(
            "checks.check_rng",
            checks.check_rng,
            lambda: dict(rng=0),
            (Arg("rng", "rng", compare=False),),
        ),
        # comcore.geometry
        T(
            "geometry.contacts",
            geometry.contacts,
            lambda: dict(mask=_mask0(), actions=list(ACTIONS0)),
            (Arg("mask", "any_mask"), ACTIONS_ARG),
        ),
        T(
            "geometry.disc_contacts",
            geometry.disc_contacts,
            lambda: dict(mask=_mask0(), actions=list(ACTIONS0), pusher_radius=1.5),
            (Arg("mask", "any_mask"), ACTIONS_ARG, Arg("pusher_radius", "nonneg")),
        ),
        T(
            "geometry.largest_component",
            geometry.largest_component,
            lambda: dict(image=_two_blobs()),
            (Arg("image", "mask_data", verdicts={"all_false": A}),),
        ),
        T(
            "geometry.outline_field",
            geometry.outline_field,
            lambda: dict(mask=_mask0()),
            (Arg("mask", "any_mask"),),
        ),
        T(
            "geometry.rasterise_polygon",
            geometry.rasterise_polygon,
            lambda: dict(vertices=[(2, 2), (20, 2), (20, 15)], shape=(30, 30)),
            (Arg("vertices", "points", verdicts={"empty_rows": R}), Arg("shape", "shape")),
        ),
        T(
            "geometry.signed_line_distance",
            geometry.signed_line_distance,
            lambda: dict(points=[(1.0, 2.0), (5.0, 5.0)], actions=list(ACTIONS0[:2])),
            (Arg("points", "points"), Arg("actions", "actions", verdicts={"misses_the_object": A})),
        ),
        T(
            "geometry.split_by_line",
            geometry.split_by_line,
            lambda: dict(mask=_mask0(), action=ACTIONS0[0]),
            (Arg("mask", "any_mask"), Arg("action", "action"), Arg("band", "nonneg")),
        ),
        T(
            "geometry.OutlineField",
            geometry.OutlineField,
            lambda: dict(mask=_mask0()),
            (Arg("mask", "any_mask"), Arg("pad", "count", verdicts={"zero": A, "10**12": R})),
        ),
        # comcore.vt
        T(
            "vt.consistent",
            vt.consistent,
            lambda: dict(
                points=np.array([[10.0, 10.0], [14.0, 14.0]]),
                contact=(4.0, 13.0),
                normal=(1.0, 0.0),
                push_dir=(1.0, 0.0),
                sense=1,
                mu=0.3,
            ),
            (
                Arg("points", "points"),
                Arg("contact", "point"),
                Arg("normal", "point"),
                Arg("push_dir", "point"),
                Arg("sense", "sense"),
                Arg("mu", "mu"),
                Arg("band", "nonneg"),
            ),
        ),
        T(
            "vt.predicted_sense",
            vt.predicted_sense,
            lambda: dict(
                com=(14.0, 10.0),
                contact=(4.0, 13.0),
                normal=(1.0, 0.0),
                push_dir=(1.0, 0.0),
                mu=0.3,
            ),
            (
                Arg("com", "points"),
                Arg("contact", "point"),
                Arg("push_dir", "point"),
                Arg("mu", "mu"),
                Arg("band", "nonneg"),
            ),
        ),
        T(
            "vt.region",
            vt.region,
            lambda: dict(mask=_mask0(), action=ACTIONS0[0], theta=0.2),
            (
                Arg("mask", "any_mask"),
                Arg("action", "action"),
                Arg("theta", "angle"),
                Arg("mu", "mu"),
                Arg("band", "nonneg"),
                Arg("theta_tol", "nonneg"),
                Arg("pusher_radius", "nonneg"),
            ),
        ),
        # simulators and predictors
        T(
            "simulators.PushSimulator.from_polygon",
            _from_polygon,
            lambda: dict(vertices_m=[(0, 0), (0.08, 0), (0.08, 0.06), (0, 0.06)]),
            (
                Arg("vertices_m", "outline", aliases=("vertices",)),
                Arg("com", "point", verdicts={"none": A}),
                Arg("mu_contact", "nonneg"),
                Arg("resolution", "length_strict"),
            ),
        ),
        T(
            "simulators.PushSimulator.push",
            lambda **kw: _sim().push(**kw),
            lambda: dict(action=(0, 19.5, 19.5, 19.5)),
            (Arg("action", "action"),),
        ),
        T(
            "predictors.EllipsoidPredictor",
            _ellipsoid,
            lambda: dict(com=(13.5, 13.5), mu_contact=0.3),
            (
                Arg("com", "point", verdicts={"none": A}),
                Arg("mu_contact", "nonneg", verdicts={"none": A}),
                Arg("pressure", str_option(("tilted", "uniform"))),
                Arg("n_steps", "count"),
            ),
        ),
        T(
            "predictors.EllipsoidPredictor.predict",
            _ellipsoid_predict,
            lambda: dict(mask=_mask0(), actions=np.array(ACTIONS0, float)),
            (Arg("mask", "any_mask"), Arg("actions", "actions", verdicts={"misses_the_object": A})),
        ),
    ]
    return [t for t in targets if _extras_present(t.name)]


def _extras_present(name: str) -> bool:
    """Whether a target's package imports and its baseline runs (``simulators`` needs ``sim``)."""
    if not name.startswith(("simulators.", "predictors.")):
        return True
    try:
        _sim().push((0, 19.5, 19.5, 19.5)) if name.startswith("simulators.") else _ellipsoid()
    except ImportError as exc:
        print(f"left out {name}: {exc}", file=sys.stderr)
        return False
    return True


def _verify_estimate_session(result, kwargs):
    return _verify_estimate(result, {"mask": _mask0()})


# ---------------------------------------------------------------------------------------
# Toy targets: known cases for the classifier (the tests run them through the pool).


def _toy_index_error(x):
    return [1.0, 2.0][int(x)]  # x = 5: an IndexError that names nothing


def _toy_nan(x):
    return float(x) * 0.0  # NaN for a NaN, no refusal


def _toy_nan_for_odd(x):
    return math.sqrt(x) if x >= 0 else math.nan  # a may_accept -1 answered with NaN


def _toy_sleep(x):
    if x == 2:
        time.sleep(60)
    return x


def _toy_clear(x):
    if not math.isfinite(x):
        raise ValueError(f"x must be a finite number, got {x!r}")
    return x


def _toy_vague(x):
    if not math.isfinite(x):
        raise ValueError("bad input")
    return x


def _toy_numpy_error(x):
    return np.ones(3) + np.ones(int(x))  # x = 2: numpy's broadcast error


def _toy_mutates(points):
    points[0] = 0.0
    return len(points)


def _toy_dies(x):
    if x == 2:
        os._exit(3)
    return x


def _toy_allocates(x):
    return float(np.empty(int(x * 1e8)).size)  # x = 20: 16 GB of address space


def toy_targets() -> list[Target]:
    """Toy functions whose class is known: the tests' cases for the classifier and the pool."""

    def one(label, value, verdict):
        return (_c(label, value, verdict),)

    def baseline_x(value=1.0):
        return lambda: dict(x=value)

    def toy(name, call, odd, base=None):
        return Target(name, call, base or baseline_x(), (Arg("x", odd),))

    return [
        toy("toy_index_error", _toy_index_error, one("five", 5, A), baseline_x(0)),
        toy("toy_nan", _toy_nan, one("nan", math.nan, R)),
        toy("toy_nan_for_odd", _toy_nan_for_odd, one("negative", -1.0, A)),
        toy("toy_sleep", _toy_sleep, one("two", 2, A)),
        toy("toy_clear", _toy_clear, one("nan", math.nan, R)),
        toy("toy_vague", _toy_vague, one("nan", math.nan, R)),
        toy("toy_numpy_error", _toy_numpy_error, one("two", 2, A), baseline_x(3)),
        toy("toy_accepts", _toy_clear, one("two", 2.0, A)),
        toy("toy_silent", _toy_clear, one("huge", 1e300, R)),
        Target(
            "toy_mutates",
            _toy_mutates,
            lambda: dict(points=[1.0]),
            (Arg("points", (_f("array", lambda rng, base: np.ones(3), A),)),),
        ),
        toy("toy_dies", _toy_dies, one("two", 2, A)),
        toy("toy_allocates", _toy_allocates, one("twenty", 20, A), baseline_x(0.01)),
    ]


# ---------------------------------------------------------------------------------------
# The plan, the classifier and the pool.


@dataclass(frozen=True)
class Case:
    """One call: a target, the argument replaced (None: the baseline) and the value's index."""

    case_id: int
    target: int
    arg: str | None
    entry: int


def plan(targets: list[Target], seed: int, n: int | None) -> list[Case]:
    """The first ``n`` cases: a baseline per target, then each (target, arg, value), permuted."""
    baselines = [(t, None, -1) for t in range(len(targets))]
    triples = [
        (t, arg.name, e)
        for t, target in enumerate(targets)
        for arg in target.args
        for e in range(len(arg.catalogue()))
    ]
    order = np.random.default_rng(seed).permutation(len(triples))
    chosen = baselines + [triples[i] for i in order]
    if n is not None:
        chosen = chosen[:n]
    return [Case(i, t, a, e) for i, (t, a, e) in enumerate(chosen)]


NUMERIC_MODULES = ("numpy", "scipy")
CLEAR_TYPES = (TypeError, ValueError, comcore.ComcoreError)


def names_argument(message: str, names: tuple[str, ...]) -> bool:
    """Whether ``message`` names one of ``names`` as a whole word, singular or plural.

    ``n`` in "n must be", ``action`` in "actions must have shape (n, 4)".
    """
    forms = {f for n in names for f in (n, n + "s", n.removesuffix("s")) if f}
    return any(
        re.search(rf"(?<![A-Za-z0-9_]){re.escape(f)}(?![A-Za-z0-9_])", message) for f in forms
    )


def classify(
    outcome: str,
    verdict: str,
    *,
    exc_types: tuple[str, ...] = (),
    clear_type: bool = False,
    message: str = "",
    names: tuple[str, ...] = (),
    raised_in: str = "",
    problem: str | None = None,
) -> str:
    """The class of one call (the module docstring states the rules).

    ``outcome`` is "returned", "raised", "timeout", "died" or "unbuilt"; ``clear_type``
    whether the exception is a TypeError, ValueError or ComcoreError; ``raised_in`` the
    module of the innermost frame; ``problem`` what was wrong with a returned answer.
    """
    if outcome == "timeout":
        return "hang"
    if outcome == "died":
        return "crash"
    if outcome == "unbuilt":
        return "harness_error"
    if outcome == "raised":
        if verdict == VALID:
            return "baseline_failed"
        from_numeric = raised_in.split(".")[0] in NUMERIC_MODULES
        if clear_type and not from_numeric and names_argument(message, names):
            return "refused_clearly"
        return "unclear_error"
    if verdict == R or problem is not None:
        return "silent"
    return "accepted"


def find_nonfinite(value, path="result", depth=0, seen=None) -> str | None:
    """The path of a NaN or inf in ``value`` (arrays, numbers, tuples, dicts, dataclasses)."""
    seen = set() if seen is None else seen
    if depth > 4 or id(value) in seen:
        return None
    seen.add(id(value))
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None:
        return None
    if isinstance(value, (float, complex, np.floating, np.complexfloating)):
        return None if np.isfinite(value) else path
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc" and value.size and not np.all(np.isfinite(value)):
            return path
        return None
    if isinstance(value, tuple) and hasattr(value, "_fields"):
        items = [(f".{f}", getattr(value, f)) for f in value._fields]
    elif isinstance(value, (tuple, list)):
        items = [(f"[{i}]", v) for i, v in enumerate(value[:50])]
    elif isinstance(value, dict):
        items = [(f"[{k!r}]", v) for k, v in list(value.items())[:50]]
    elif is_dataclass(value) and not isinstance(value, type):
        items = [(f".{f.name}", getattr(value, f.name, None)) for f in fields(value)]
    else:
        return None
    for suffix, item in items:
        found = find_nonfinite(item, path + suffix, depth + 1, seen)
        if found:
            return found
    return None


def describe(value) -> str:
    """A short repr of a catalogue value, for the reproducer."""
    if isinstance(value, comcore.Mask):
        return f"Mask(shape={value.shape}, area_px={value.area_px}, resolution={value.resolution})"
    if isinstance(value, np.ndarray):
        text = f"ndarray(shape={value.shape}, dtype={value.dtype})"
        if value.size <= 12:
            text += f" {np.array2string(value, threshold=12)}".replace("\n", "")
        return text
    if callable(value) and getattr(value, "__name__", "") == "<lambda>":
        try:
            return f"lambda returning {value(None)!r}"
        except Exception:
            return "a lambda"
    text = repr(value)
    return text if len(text) <= 160 else text[:157] + "..."


def _base(target, arg, kwargs):
    """An argument's baseline value: the baseline call's, the Arg's own, or the default."""
    if arg.name in kwargs:
        return kwargs[arg.name]
    return arg.base() if arg.base is not None else _default(target.call, arg.name)


def _default(call, name):
    """The default of ``call``'s parameter ``name`` where it has a number, else 1.0."""
    try:
        default = inspect.signature(call).parameters[name].default
    except (KeyError, TypeError, ValueError):
        return 1.0
    return default if isinstance(default, (int, float)) and not isinstance(default, bool) else 1.0


def _pickled(value):
    if isinstance(value, comcore.Mask):  # a Mask caches what it derives: compare its pixels
        value = (value.data, value.resolution)
    try:
        return pickle.dumps(value)
    except Exception:
        return None


def run_case(targets: list[Target], case: Case, seed: int, show_traceback: bool = False) -> dict:
    """Build one case's arguments, call it and describe what happened (in this process)."""
    target = targets[case.target]
    row = dict(
        case=case.case_id,
        function=target.name,
        argument=case.arg or "(baseline)",
        label="(baseline)",
        verdict=VALID,
        value="",
        outcome="",
        exception="",
        message="",
        raised_in="",
        problem=None,
        mutated=False,
        warnings=[],
        seconds=0.0,
    )
    names: tuple[str, ...] = ()
    try:
        kwargs = target.baseline()
        if case.arg is not None:
            arg = next(a for a in target.args if a.name == case.arg)
            odd = arg.catalogue()[case.entry]
            rng = np.random.default_rng([seed, case.case_id])
            value = odd.make(rng, _base(target, arg, kwargs))
            kwargs[arg.name] = value
            names = arg.names()
            row.update(label=odd.label, verdict=odd.verdict, value=describe(value))
            compared = {arg.name: _pickled(value)} if arg.compare else {}
        else:
            compared = {}
    except Exception as exc:
        row.update(outcome="unbuilt", exception=type(exc).__name__, message=str(exc)[:300])
        row["class"] = classify("unbuilt", row["verdict"])
        return row
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = target.call(**kwargs)
        except BaseException as exc:
            if show_traceback:
                traceback.print_exc()
            row["seconds"] = time.perf_counter() - start
            tb = traceback.extract_tb(exc.__traceback__)
            frame_file = tb[-1].filename if tb else ""
            row.update(
                outcome="raised",
                exception=type(exc).__name__,
                message=(str(exc) if not isinstance(exc, KeyError) else repr(exc))[:300],
                raised_in=_module_of(frame_file),
            )
            row["class"] = classify(
                "raised",
                row["verdict"],
                clear_type=isinstance(exc, CLEAR_TYPES),
                message=row["message"],
                names=names,
                raised_in=row["raised_in"],
            )
            result = None
        else:
            row["seconds"] = time.perf_counter() - start
            problem = find_nonfinite(result)
            problem = None if problem in target.nonfinite_ok else problem
            problem = f"NaN or inf at {problem}" if problem else None
            if problem is None and target.verify is not None:
                problem = target.verify(result, kwargs)
            row.update(outcome="returned", problem=problem)
            row["class"] = classify("returned", row["verdict"], problem=problem)
    row["warnings"] = sorted({f"{w.category.__name__}: {str(w.message)[:80]}" for w in caught})[:3]
    for name, before in compared.items():
        if before is not None and _pickled(kwargs[name]) != before:
            row["mutated"] = True
    return row


def _module_of(filename: str) -> str:
    """The dotted module of a source file, from its path (site-packages or the repository)."""
    parts = filename.replace("\\", "/").split("/")
    for anchor in ("site-packages", "dist-packages"):
        if anchor in parts:
            parts = parts[parts.index(anchor) + 1 :]
            break
    else:
        for top in ("comcore", "predictors", "simulators", "numpy", "scipy"):
            if top in parts:
                parts = parts[len(parts) - 1 - parts[::-1].index(top) :]
                break
        else:
            parts = parts[-1:]
    return ".".join(parts).removesuffix(".py")


def _child(conn, targets, case, seed, memory_bytes):
    if memory_bytes:
        try:
            resource.setrlimit(resource.RLIMIT_AS, (memory_bytes, memory_bytes))
        except (ValueError, OSError):
            pass
    try:
        row = run_case(targets, case, seed)
    except BaseException as exc:
        row = dict(
            case=case.case_id,
            outcome="unbuilt",
            exception=type(exc).__name__,
            message=str(exc)[:300],
        )
        row["class"] = "harness_error"
    try:
        conn.send(row)
    finally:
        conn.close()
        os._exit(0)


def run_pool(
    targets: list[Target],
    cases: list[Case],
    seed: int,
    *,
    timeout: float,
    workers: int,
    memory_bytes: int,
    progress: bool = False,
) -> list[dict]:
    """Run each case in a forked child, ``workers`` at a time; one past ``timeout`` is killed."""
    ctx = mp.get_context("fork")
    pending = list(reversed(cases))
    running: dict[
        Any, tuple[Case, Any, float, Any]
    ] = {}  # reader -> (case, process, deadline, writer)
    rows: dict[int, dict] = {}
    done = 0
    while pending or running:
        while pending and len(running) < workers:
            case = pending.pop()
            reader, writer = ctx.Pipe(duplex=False)
            proc = ctx.Process(
                target=_child, args=(writer, targets, case, seed, memory_bytes), daemon=True
            )
            proc.start()
            writer.close()
            running[reader] = (case, proc, time.monotonic() + timeout, writer)
        wait_for = max(0.0, min(d for _, _, d, _ in running.values()) - time.monotonic())
        ready = mpc.wait(list(running), timeout=wait_for)
        now = time.monotonic()
        for reader in list(running):
            case, proc, deadline, _ = running[reader]
            row = None
            if reader in ready:
                try:
                    row = reader.recv()
                except (EOFError, OSError):
                    proc.join(1)
                    row = _bare_row(targets, case, seed, "died", f"exit code {proc.exitcode}")
            elif now >= deadline:
                proc.kill()
                row = _bare_row(targets, case, seed, "timeout", f"over {timeout:g} s")
            if row is None:
                continue
            proc.join(5)
            reader.close()
            del running[reader]
            rows[case.case_id] = row
            done += 1
            if progress and done % 200 == 0:
                print(f"  {done} / {len(cases)} calls", file=sys.stderr, flush=True)
    return [rows[c.case_id] for c in cases]


def _bare_row(targets, case, seed, outcome, message):
    target = targets[case.target]
    row = dict(
        case=case.case_id,
        function=target.name,
        argument=case.arg or "(baseline)",
        label="(baseline)",
        verdict=VALID,
        value="",
        outcome=outcome,
        exception="",
        message=message,
        raised_in="",
        problem=None,
        mutated=False,
        warnings=[],
        seconds=None,
    )
    if case.arg is not None:
        arg = next(a for a in target.args if a.name == case.arg)
        odd = arg.catalogue()[case.entry]
        row.update(label=odd.label, verdict=odd.verdict)
        try:  # the child's value, rebuilt here from the same generator for the reproducer
            base = _base(target, arg, target.baseline())
            row["value"] = describe(odd.make(np.random.default_rng([seed, case.case_id]), base))
        except Exception:
            pass
    row["class"] = classify(outcome, row["verdict"])
    return row


# ---------------------------------------------------------------------------------------
# The report.


def report(rows: list[dict], examples: int) -> str:
    """Counts per class, per function, and the first examples per (function, class)."""
    lines = []
    totals = Counter(r["class"] for r in rows)
    shown = [c for c in CLASSES if totals[c]]
    lines.append("| class | calls |")
    lines.append("| --- | --- |")
    for c in CLASSES:
        lines.append(f"| {c} | {totals[c]} |")
    lines.append(f"| mutated an input | {sum(bool(r.get('mutated')) for r in rows)} |")
    lines.append(f"| all | {len(rows)} |")
    lines.append("")
    by_function = defaultdict(Counter)
    for r in rows:
        by_function[r["function"]][r["class"]] += 1
        by_function[r["function"]]["mutated"] += bool(r.get("mutated"))
    lines.append("| function | " + " | ".join(shown) + " | mutated |")
    lines.append("| --- |" + " --- |" * (len(shown) + 1))
    for name, counts in by_function.items():
        lines.append(
            f"| {name} | " + " | ".join(str(counts[c]) for c in shown) + f" | {counts['mutated']} |"
        )
    lines.append("")
    lines.append("Examples (function, argument = value: what happened; replay with --replay ID):")
    groups = defaultdict(list)
    for r in rows:
        if r["class"] != "accepted" and r["class"] != "refused_clearly":
            groups[(r["function"], r["class"])].append(r)
        if r.get("mutated"):
            groups[(r["function"], "mutated")].append(r)
    for (name, cls), items in groups.items():
        lines.append(f"  {name}: {cls} ({len(items)})")
        for r in items[:examples]:
            what = (
                r["problem"] if r["outcome"] == "returned" else f"{r['exception']}: {r['message']}"
            )
            where = f" [in {r['raised_in']}]" if r.get("raised_in") else ""
            lines.append(
                f"    #{r['case']} {r['argument']} = {r['label']} {r['value']}: "
                f"{what or 'returned'}{where}"[:400]
            )
    return "\n".join(lines)


def _hung(case_id, timeout):
    print(f"case {case_id}: hang (over {timeout:g} s)", file=sys.stderr, flush=True)
    os._exit(124)


def main(argv=None) -> int:
    """Parse the options, run the cases and print the report."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--n", type=int, default=0, help="calls (default 0: every case once)")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds per call")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--memory-gb", type=float, default=4.0, help="address-space limit per call")
    parser.add_argument("--examples", type=int, default=3, help="examples per (function, class)")
    parser.add_argument("--json", help="write every row to this file")
    parser.add_argument("--targets", choices=("api", "toy"), default="api")
    parser.add_argument("--functions", help="comma-separated target names (default: all)")
    parser.add_argument("--replay", type=int, help="run this case id here and print its traceback")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    args = parser.parse_args(argv)
    targets = api_targets() if args.targets == "api" else toy_targets()
    if args.functions:
        wanted = set(args.functions.split(","))
        targets = [t for t in targets if t.name in wanted]
    n = None if args.n == 0 else args.n
    if args.replay is not None:
        cases = plan(targets, args.seed, max(n or 0, args.replay + 1))
        case = cases[args.replay]
        # the pool's limits, here: SIGALRM ends a hang, RLIMIT_AS turns a huge allocation
        # into a MemoryError
        memory = int(args.memory_gb * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (memory, resource.getrlimit(resource.RLIMIT_AS)[1]))
        signal.signal(signal.SIGALRM, lambda *_: _hung(case.case_id, args.timeout))
        signal.alarm(math.ceil(args.timeout))
        row = run_case(targets, case, args.seed, show_traceback=True)
        signal.alarm(0)
        print(json.dumps(row, indent=1, default=str))
        return 0
    cases = plan(targets, args.seed, n)
    if args.list:
        for c in cases:
            t = targets[c.target]
            label = (
                "(baseline)"
                if c.arg is None
                else next(a for a in t.args if a.name == c.arg).catalogue()[c.entry].label
            )
            print(c.case_id, t.name, c.arg or "(baseline)", label)
        return 0
    start = time.perf_counter()
    rows = run_pool(
        targets,
        cases,
        args.seed,
        timeout=args.timeout,
        workers=args.workers,
        memory_bytes=int(args.memory_gb * 2**30),
        progress=True,
    )
    wall = time.perf_counter() - start
    distinct = len(plan(targets, args.seed, None))
    print(
        f"{len(rows)} calls of {len(targets)} functions (seed {args.seed}, "
        f"{distinct} distinct cases), timeout {args.timeout:g} s, {args.workers} workers, "
        f"{args.memory_gb:g} GB each: {wall:.0f} s"
    )
    print()
    print(report(rows, args.examples))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(
                dict(seed=args.seed, n=len(rows), wall_s=wall, rows=rows), f, indent=0, default=str
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())

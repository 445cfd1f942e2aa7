"""Tests of predictors.ellipsoid: the ellipsoidal limit-surface model and its fit."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import comcore
from comcore.geometry import outline_field
from predictors import EllipsoidFit, EllipsoidPredictor
from predictors.ellipsoid._model import body_twist
from predictors.ellipsoid._support import (
    _characteristic_length_sq,
    _tilted_weights,
    characteristic_length_sq,
)


def plate(h=20, w=30, pad=10):
    return comcore.Mask(np.pad(np.ones((h, w), bool), pad))


def notched_ellipse():
    yy, xx = np.mgrid[:80, :80]
    img = ((xx - 40) ** 2 / 30**2 + (yy - 40) ** 2 / 22**2) < 1
    img[40:, 30:50] = False  # concave
    return comcore.Mask(img)


@pytest.fixture(scope="module")
def blob():
    return notched_ellipse()


# -- the model's known cases ---------------------------------------------------------


@pytest.mark.parametrize("mu", [0.1, 0.5, np.inf])
@pytest.mark.parametrize("com_x", [18.0, 24.5, 33.0])
def test_push_through_com_along_normal_does_not_rotate(mu, com_x):
    mask = plate()  # object rows 10..29, columns 10..39
    com_y = 17.0
    p = EllipsoidPredictor(com=(com_x, com_y), mu_contact=mu)
    out = p.predict(mask, [(0, com_y, 21.5, com_y), (com_x, 0, com_x, 21.5)])
    assert np.abs(out[:, 0]).max() < 1e-5  # radians; float round-off of the smoothed outline
    np.testing.assert_allclose(out[:, 1:], [[12.0, 0.0], [0.0, 12.0]], atol=1e-4)


def test_oblique_push_through_com_while_sticking_does_not_rotate():
    rng = np.random.default_rng(0)
    r = rng.normal(size=(100, 2)) * 10
    normal = -r / np.linalg.norm(r, axis=1, keepdims=True)  # contact facing the CoM
    u = -r / np.linalg.norm(r, axis=1, keepdims=True)  # along the line through the CoM
    _, omega, sticking = body_twist(r, comcore.conventions.rotate_vectors(normal, 0.3), u, 25.0, np.inf)
    assert sticking.all()
    assert np.abs(omega).max() < 1e-12


def test_sticking_matches_lynch_closed_form():
    # Lynch, Maekawa and Tanie (1992), in a right-handed frame (X = x, Y = -y).
    rng = np.random.default_rng(1)
    n = 200
    r = rng.uniform(-15, 15, (n, 2))
    normal = np.column_stack([np.cos(a := rng.uniform(0, 2 * np.pi, n)), np.sin(a)])
    u = comcore.conventions.rotate_vectors(normal, rng.uniform(-0.6, 0.6, n))
    c2 = rng.uniform(20, 100, n)
    v, omega, sticking = body_twist(r, normal, u, c2, np.inf)
    assert sticking.all()
    xc, yc = r[:, 0], -r[:, 1]
    vpx, vpy = u[:, 0], -u[:, 1]
    den = c2 + xc**2 + yc**2
    vx = ((c2 + xc**2) * vpx + xc * yc * vpy) / den
    vy = (xc * yc * vpx + (c2 + yc**2) * vpy) / den
    np.testing.assert_allclose(v[:, 0], vx, atol=1e-12)
    np.testing.assert_allclose(-v[:, 1], vy, atol=1e-12)
    np.testing.assert_allclose(omega, (xc * vy - yc * vx) / c2, atol=1e-12)


def _contact_velocity(r, v, omega):
    return v + omega[..., None] * np.stack([r[..., 1], -r[..., 0]], axis=-1)


def test_sliding_contact_obeys_coulomb_and_the_normal_constraint():
    rng = np.random.default_rng(2)
    n = 400
    r = rng.uniform(-15, 15, (n, 2))
    normal = comcore.conventions.rotate_vectors([[1.0, 0.0]], rng.uniform(0, 2 * np.pi, n))
    u = comcore.conventions.rotate_vectors(normal, rng.uniform(-1.4, 1.4, n))
    mu = 0.2
    v, omega, sticking = body_twist(r, normal, u, 40.0, mu)
    assert 0.1 < sticking.mean() < 0.9  # both regimes are exercised
    vc = _contact_velocity(r, v, omega)
    np.testing.assert_allclose(np.sum(vc * normal, axis=1), np.sum(u * normal, axis=1), atol=1e-9)
    np.testing.assert_allclose(vc[sticking], u[sticking], atol=1e-9)
    slide = ~sticking
    # The force (parallel to v) lies on the friction-cone edge ...
    f = v[slide] / np.linalg.norm(v[slide], axis=1, keepdims=True)
    cos_f = np.sum(f * normal[slide], axis=1)
    np.testing.assert_allclose(cos_f, 1 / np.hypot(1, mu), atol=1e-9)
    # ... on the side towards which the pusher slips over the object.
    slip = comcore.conventions.ccw_cross(normal[slide], u[slide] - vc[slide])
    assert np.all(np.sign(slip) == np.sign(comcore.conventions.ccw_cross(normal[slide], f)))
    # and the rotation follows the ellipsoid: omega / |v| = moment / c^2.
    np.testing.assert_allclose(
        omega[slide] / np.linalg.norm(v[slide], axis=1),
        comcore.conventions.ccw_cross(r[slide], f) / 40.0,
        atol=1e-9,
    )


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.9])
def test_instantaneous_sense_is_the_voting_theorem(blob, mu):
    rng = np.random.default_rng(3)
    acts = comcore.sample_pushes(blob, 40, cone=0.7, rng=4)
    con = comcore.geometry.contacts(blob, acts)
    coms = blob.pixels[rng.choice(blob.area_px, 200, replace=False)]
    c2 = characteristic_length_sq(blob, coms)
    for i in range(len(acts)):
        push = (acts[i, 2:] - acts[i, :2]) / np.linalg.norm(acts[i, 2:] - acts[i, :2])
        _, omega, _ = body_twist(con.point[i] - coms, con.normal[i], push, c2, mu)
        sense = comcore.vt.predicted_sense(coms, con.point[i], con.normal[i], push, mu)
        # CoMs on the push line itself are round-off ties for both.
        off_line = np.abs(comcore.conventions.ccw_cross(con.point[i] - coms, push)) > 1e-9
        np.testing.assert_array_equal(np.sign(omega)[off_line], sense[off_line])


def test_integrated_sense_agrees_with_voting_theorem_away_from_its_lines():
    # A smooth outline: at corners the contact normal (hence the vote) is ill-defined.
    yy, xx = np.mgrid[:80, :80]
    blob = comcore.Mask(((xx - 40) ** 2 / 30**2 + (yy - 40) ** 2 / 22**2) < 1)
    mu = 0.3
    rng = np.random.default_rng(5)
    acts = comcore.sample_pushes(blob, 40, cone=0.7, rng=6)
    con = comcore.geometry.contacts(blob, acts)
    coms = blob.pixels[rng.choice(blob.area_px, 150, replace=False)]
    theta = EllipsoidPredictor().predict_hypotheses(blob, acts, coms, mu)[..., 0]
    agree, total = 0, 0
    for i in range(len(acts)):
        push = acts[i, 2:] - acts[i, :2]
        sense = comcore.vt.predicted_sense(coms, con.point[i], con.normal[i], push, mu)
        rays = comcore.conventions.rotate_vectors(
            np.tile(con.normal[i], (2, 1)), [np.arctan(mu), -np.arctan(mu)]
        )
        rays = np.vstack([rays, push / np.linalg.norm(push)])
        margin = np.abs(comcore.conventions.ccw_cross((coms - con.point[i])[:, None, :], rays)).min(axis=1)
        sel = (margin > 2.0) & (np.abs(theta[:, i]) > np.radians(1.0))
        agree += int((comcore.conventions.rotation_sense(theta[sel, i]) == sense[sel]).sum())
        total += int(sel.sum())
    assert total > 3000
    assert agree / total >= 0.99


def test_contact_sticks_to_the_pusher_and_motion_moves_the_area_centroid():
    # With infinite friction the body point first touched ends at the pusher's end.
    mask = plate()
    com = (16.0, 25.0)  # far from the area centroid (24.5, 19.5)
    acts = np.array([[0.0, 14.0, 20.0, 14.0], [0.0, 26.0, 14.0, 22.0], [20.0, 0.0, 24.0, 20.0]])
    out = EllipsoidPredictor(com=com, mu_contact=np.inf, n_steps=200).predict(mask, acts)
    assert np.abs(out[:, 0]).min() > 0.05
    con = comcore.geometry.contacts(mask, acts)
    for i in range(len(acts)):
        moved = comcore.apply_motion(con.point[i], out[i, 0], out[i, 1:], mask.centroid)
        assert np.linalg.norm(moved - acts[i, 2:]) < 0.35


def test_sliding_pusher_stays_on_the_moved_outline(blob):
    acts = comcore.sample_pushes(blob, 30, cone=1.0, rng=7)
    out = EllipsoidPredictor(com=(35.0, 30.0), mu_contact=0.1).predict(blob, acts)
    field = outline_field(blob)
    # The pusher's end, taken back into the object's initial frame, is on the
    # outline, or off it when the pusher slid past the end of an edge; never inside.
    gap = np.empty(len(acts))
    for i in range(len(acts)):
        body = comcore.apply_motion(acts[i, 2:] - out[i, 1:], -out[i, 0], (0, 0), blob.centroid)
        gap[i] = field.sample(body[..., 0], body[..., 1])[0]
    assert gap.min() > -0.15
    assert np.mean(gap < 0.15) >= 0.9


def test_mirror_symmetry():
    mask = notched_ellipse()
    mirrored = comcore.Mask(mask.data[:, ::-1])
    w = mask.shape[1] - 1
    acts = comcore.sample_pushes(mask, 20, cone=0.6, rng=8)
    flip = acts * [-1, 1, -1, 1] + [w, 0, w, 0]
    a = EllipsoidPredictor(com=(30.0, 35.0), mu_contact=0.3).predict(mask, acts)
    b = EllipsoidPredictor(com=(w - 30.0, 35.0), mu_contact=0.3).predict(mirrored, flip)
    # exact but for the pixel blocks of the support, which are not mirror images
    np.testing.assert_allclose(b, a * [-1, -1, 1], atol=1e-3)


def test_rotation_grows_with_the_lever_arm():
    mask = plate(20, 60)
    p = EllipsoidPredictor(com=mask.centroid, mu_contact=0.5)
    cx = mask.centroid[0]
    offsets = np.arange(1, 9)
    acts = np.column_stack([cx + offsets, 0 * offsets, cx + offsets, 0 * offsets + 21.5])
    theta = p.predict(mask, acts)[:, 0]
    assert np.all(np.diff(np.abs(theta)) > 0)
    assert np.all(theta < 0)  # pushing down (+y) right of the CoM: clockwise on screen


def test_missing_push_does_not_move():
    mask = plate()
    out = EllipsoidPredictor(com=mask.centroid).predict(mask, [(0, 2, 50, 2)])
    np.testing.assert_array_equal(out, np.zeros((1, 3)))


def test_disc_pusher_is_led_by_its_leading_point():
    mask = plate()  # object rows 10..29, columns 10..39
    normal_push = [(0, 19.5, 20, 19.5)]
    point = EllipsoidPredictor(com=mask.centroid).predict(mask, normal_push)
    disc = EllipsoidPredictor(com=mask.centroid, pusher_radius=0.004)
    np.testing.assert_allclose(disc.predict(mask, normal_push), point, atol=1e-9)
    # A path 1 px past the top-left corner: a point misses, a 1.6 px disc clips the corner.
    grazing = [(0, 8.5, 30, 8.5)]
    assert not EllipsoidPredictor(com=mask.centroid).predict(mask, grazing).any()
    assert disc.predict(mask, grazing)[0, 0] > 0.01  # clipped above the CoM: CCW on screen


def test_characteristic_length_of_a_uniform_disc():
    yy, xx = np.mgrid[:161, :161]
    disc = comcore.Mask((xx - 80) ** 2 + (yy - 80) ** 2 <= 75**2)
    c2 = characteristic_length_sq(disc, [disc.centroid], "uniform")
    assert np.sqrt(c2[0]) == pytest.approx(2 * 75 / 3, rel=0.01)
    off = (110.0, 80.0)
    uniform_off = characteristic_length_sq(disc, [off], "uniform")[0]
    for pressure in ("linear", "tilted"):
        c2p = characteristic_length_sq(disc, [disc.centroid, off], pressure)
        assert c2p[0] == pytest.approx(c2[0], rel=1e-9)
        assert c2p[1] < uniform_off  # pressure concentrated near the CoM


@pytest.mark.parametrize("limit_surface", ["rotation", "directional"])
def test_remembered_lengths_equal_fresh_ones(blob, limit_surface):
    """Pixel-centre CoMs come from the per-mask table, others are computed; same values."""
    h, w = blob.shape
    coms = np.vstack(
        [blob.pixels[::7], blob.pixels[:4] + 0.25, [[-1.0, 3.0], [w + 2.0, h - 1.0]]]
    )
    fresh = _characteristic_length_sq(blob, coms, "tilted", limit_surface)
    first = characteristic_length_sq(blob, coms, "tilted", limit_surface)
    again = characteristic_length_sq(blob, coms[::-1], "tilted", limit_surface)[::-1]
    np.testing.assert_allclose(first, fresh, rtol=1e-12)
    np.testing.assert_array_equal(again, first)  # the second call reads the table


def test_tilted_pressure_has_its_centre_at_the_com(blob):
    coms = blob.pixels[::37]
    depth = outline_field(blob).sample(coms[:, 0], coms[:, 1])[0]
    coms = coms[depth < -2.0]  # 2 px inside the outline
    w = _tilted_weights(blob.pixels, coms)
    np.testing.assert_allclose(w @ blob.pixels / w.sum(axis=1, keepdims=True), coms, atol=1e-3)


# -- vectorisation, protocol, fit -------------------------------------------------------


def test_vectorised_equals_loop(blob):
    p = EllipsoidPredictor(pressure="linear", pusher_radius=0.003)
    acts = comcore.sample_pushes(blob, 6, cone=0.5, rng=9)
    coms = blob.pixels[::150]
    batch = p.predict_hypotheses(blob, acts, coms, 0.4)
    assert batch.shape == (len(coms), 6, 3)
    for i, com in enumerate(coms):
        single = EllipsoidPredictor(com=com, mu_contact=0.4, pressure="linear",
                                    pusher_radius=0.003)  # fmt: skip
        for j, act in enumerate(acts):
            np.testing.assert_allclose(single.predict(blob, act[None])[0], batch[i, j], atol=1e-12)


def test_is_a_predictor_and_a_hypothesis_predictor(blob):
    p = EllipsoidPredictor(com=blob.centroid, mu_contact=0.3)
    assert isinstance(p, comcore.Predictor)
    assert isinstance(p, comcore.Predictor)
    out = comcore.motion.predict_motions(p, blob, comcore.sample_pushes(blob, 3, rng=0))
    assert out.shape == (3, 3)


def _priors(mask, com, mu, n=12, seed=0, noise=0.0):
    acts = comcore.sample_pushes(mask, n, cone=0.5, rng=seed)
    mots = EllipsoidPredictor(com=com, mu_contact=mu).predict(mask, acts)
    rng = np.random.default_rng(seed)
    mots = mots + rng.normal(size=mots.shape) * noise * np.array([np.radians(1), 1, 1])
    return [(comcore.Action(*a), comcore.Motion(*m)) for a, m in zip(acts, mots)]


@pytest.mark.parametrize("com,mu", [((25.3, 47.6), 0.2), ((60.2, 38.9), 0.65)])
def test_fit_recovers_com_and_mu_from_model_priors(blob, com, mu):
    priors = _priors(blob, com, mu)
    fit = EllipsoidPredictor().fit(blob, priors)
    assert isinstance(fit, EllipsoidFit)
    assert np.hypot(*(np.subtract(fit.com, com))) < 0.5  # sub-pixel
    if mu < 0.4:  # pushes within 0.5 rad of the normal slide: mu is identifiable
        assert abs(fit.mu_contact - mu) <= 0.02
    refit = EllipsoidPredictor(com=fit.com, mu_contact=fit.mu_contact)
    observed = np.array([m for _, m in priors])
    replay = refit.predict(blob, [a for a, _ in priors])
    assert np.degrees(np.abs(replay[:, 0] - observed[:, 0])).max() < 1.0
    assert np.all(np.linalg.eigvalsh(fit.com_cov) > 0)
    assert fit.weights.sum() == pytest.approx(1.0)
    assert not fit.com_cov.flags.writeable and not fit.candidates.flags.writeable
    assert fit.com_m == pytest.approx(np.multiply(fit.com, blob.resolution))


def test_fit_with_noisy_priors_is_close_and_honest(blob):
    com = (45.0, 30.0)
    fit = EllipsoidPredictor().fit(blob, _priors(blob, com, 0.3, n=12, seed=1, noise=1.0))
    err = np.subtract(fit.com, com)
    assert np.hypot(*err) < 3.0
    # the truth lies within the fitted uncertainty (Mahalanobis distance < 3)
    assert err @ np.linalg.solve(fit.com_cov, err) < 9.0
    assert fit.residual_scale[0] >= np.radians(3.0) - 1e-12  # the floor: model error


def test_predict_fits_then_predicts(blob):
    com, mu = (30.0, 25.0), 0.3
    priors = _priors(blob, com, mu)
    queries = comcore.sample_pushes(blob, 10, cone=0.5, rng=11)
    truth = EllipsoidPredictor(com=com, mu_contact=mu).predict(blob, queries)
    pred = EllipsoidPredictor().predict(blob, queries, priors)
    assert np.degrees(np.abs(pred[:, 0] - truth[:, 0])).mean() < 1.0


def test_known_com_fits_only_mu(blob):
    com = (30.0, 25.0)
    fit = EllipsoidPredictor(com=com).fit(blob, _priors(blob, com, 0.2))
    assert fit.com == com and np.all(fit.com_cov == 0)
    assert abs(fit.mu_contact - 0.2) < 0.05


def test_fit_to_estimate(blob):
    fit = EllipsoidPredictor().fit(blob, _priors(blob, (30.0, 25.0), 0.3))
    est = fit.to_estimate(blob)
    assert est.ok and est.region[25, 30] and est.covariance.shape == (2, 2)


def test_inputs_are_not_mutated(blob):
    acts = comcore.sample_pushes(blob, 4, rng=0)
    coms = blob.pixels[:3].copy()
    before = acts.copy(), coms.copy()
    EllipsoidPredictor().predict_hypotheses(blob, acts, coms, 0.3)
    np.testing.assert_array_equal(acts, before[0])
    np.testing.assert_array_equal(coms, before[1])


# -- bad input --------------------------------------------------------------------------


def test_needs_com_or_priors(blob):
    with pytest.raises(ValueError, match="needs a CoM: give com"):
        EllipsoidPredictor().predict(blob, [(0, 40, 20, 40)])
    with pytest.raises(ValueError, match="priors must hold at least one"):
        EllipsoidPredictor().fit(blob, [])


@pytest.mark.parametrize(
    "kwargs,error,match",
    [
        ({"com": (1.0, 2.0, 3.0)}, ValueError, "com must have shape"),
        ({"com": [(1, 2), (3, 4)]}, ValueError, "com must be a single point"),
        ({"mu_contact": -0.1}, ValueError, "mu_contact must be a number >= 0"),
        ({"mu_contact": "high"}, TypeError, "mu_contact must be a number"),
        ({"pressure": "gaussian"}, ValueError, "pressure must be one of"),
        ({"pusher_radius": -1.0}, ValueError, "pusher_radius"),
        ({"n_steps": 0}, ValueError, "n_steps must be a positive integer"),
    ],
)
def test_bad_parameters(kwargs, error, match):
    with pytest.raises(error, match=match):
        EllipsoidPredictor(**kwargs)


def test_bad_call_arguments(blob):
    p = EllipsoidPredictor(com=blob.centroid, mu_contact=0.3)
    with pytest.raises(TypeError, match=r"mask must be a comcore\.Mask"):
        p.predict(blob.data, [(0, 40, 20, 40)])
    with pytest.raises(ValueError, match=r"actions must have shape \(n, 4\)"):
        p.predict(blob, [(0, 40, 20)])
    with pytest.raises(ValueError, match=r"start inside it"):
        p.predict(blob, [(40, 30, 60, 30)])
    with pytest.raises(ValueError, match="coms must have shape"):
        p.predict_hypotheses(blob, [(0, 40, 20, 40)], [[1, 2, 3]], 0.3)
    with pytest.raises(ValueError, match="mu must be a number >= 0"):
        p.predict_hypotheses(blob, [(0, 40, 20, 40)], [[40, 40]], -1)
    with pytest.raises(ValueError, match=r"priors\[0\] must be an \(Action, Motion\) pair"):
        EllipsoidPredictor().predict(blob, [(0, 40, 20, 40)], [(1, 2)])


def test_import_is_light():
    code = (
        "import sys, predictors.ellipsoid; "
        "print(any(m in sys.modules for m in ('torch', 'pymunk', 'trimesh', 'cv2', 'shapely')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.mark.slow
def test_eval_script_runs(tmp_path):
    pytest.importorskip("pymunk")
    pytest.importorskip("shapely")
    script = Path(__file__).resolve().parents[2] / "benchmarks" / "accuracy" / "eval_predictors.py"
    out = subprocess.run(
        [sys.executable, str(script), "--objects", "Obj3", "--priors", "4", "--queries", "4",
         "--out", str(tmp_path / "theta.png"), "--fit-figure", "none"],
        capture_output=True, text=True, check=True, cwd=script.parents[2],
        env={**os.environ, "PYTHONPATH": str(script.parents[2])},
    )  # fmt: skip
    assert "| ellipsoid (fitted) | all |" in out.stdout
    assert "| trivial (centroid) | all |" in out.stdout
    assert (tmp_path / "theta.png").stat().st_size > 10_000


def test_fit_speed_script_runs():
    pytest.importorskip("pymunk")
    pytest.importorskip("shapely")
    script = Path(__file__).resolve().parents[2] / "benchmarks" / "timing" / "bench_ellipsoid_fit.py"
    out = subprocess.run(
        [sys.executable, str(script), "--object", "Obj3", "--priors", "3", "--repeats", "2"],
        capture_output=True, text=True, check=True, cwd=script.parents[2],
        env={**os.environ, "PYTHONPATH": str(script.parents[2])},
    )  # fmt: skip
    lines = out.stdout.splitlines()
    assert lines[0].startswith("EllipsoidPredictor.fit: 3 priors on Obj3 (") and "n=2" in lines[0]
    assert "cold (fresh mask): median " in lines[1] and "warm (same mask):  median " in lines[2]
    assert "mm from the true one" in lines[3]

"""Tests of comcore.LimitSurfaceModel: the exact limit surface of the footprint."""

import numpy as np
import pytest

import comcore
from comcore.motion._lattice import PushLattice, pressure_table, table_pressures
from comcore.motion._pressure import pressures, support


def plate(h=20, w=30, pad=10):
    return comcore.Mask(np.pad(np.ones((h, w), bool), pad))


def notched():
    yy, xx = np.mgrid[:60, :60]
    img = ((xx - 30) ** 2 / 24**2 + (yy - 30) ** 2 / 16**2) < 1
    img[30:, 24:36] = False
    return comcore.Mask(img)


MODEL = comcore.LimitSurfaceModel(pusher_radius=0.004, node_spacing=0.0)


@pytest.mark.parametrize("family", ["linear", "tilted", "peaked"])
def test_pressure_has_its_centre_at_the_com(family):
    sup = support(plate(), 32)
    coms = np.array([[0.0, 0.0], [8.0, -4.0], [-10.0, 6.0]])  # the last one needs clipping
    p = pressures(sup, coms, family)
    assert (p >= 0).all()
    np.testing.assert_allclose(p.sum(axis=1), 1.0)
    np.testing.assert_allclose(p @ sup.points, coms, atol=1e-6)


@pytest.mark.parametrize("mu", [0.0, 0.3, np.inf])
def test_mirror_symmetric_object_mirrors_the_motion(mu):
    mask = plate()  # symmetric about x = 24.5 (the centroid's column)
    action = np.array([[18.0, 0.0, 18.0 + 4.0, 24.0]])  # down onto the top edge, slanted
    mirrored = np.array([[31.0, 0.0, 31.0 - 4.0, 24.0]])
    com, com_m = np.array([[21.0, 22.0]]), np.array([[28.0, 22.0]])
    a = MODEL.predict_hypotheses(mask, action, com, mu)[0, 0]
    b = MODEL.predict_hypotheses(mask, mirrored, com_m, mu)[0, 0]
    # Single-precision solves (1e-7 relative) over a 3 cm push: 1e-4 rad and px.
    np.testing.assert_allclose(b, [-a[0], -a[1], a[2]], atol=1e-4)


@pytest.mark.parametrize("com", [(24.5, 19.5), (20.0, 15.0)])
def test_normal_push_through_the_com_does_not_turn(com):
    mask = plate()
    push = [(com[0], 0.0, com[0], 24.0)]  # along the top edge's normal, through the CoM
    out = MODEL.predict_hypotheses(mask, push, [com], 0.3)[0, 0]
    assert abs(out[0]) < 1e-6
    assert out[2] > 10  # it translates (a 3 cm push minus the approach: 14 px)


def test_sense_agrees_with_the_voting_theorem():
    mask = notched()
    pushes = comcore.sample_pushes(mask, 8, cone=0.3, rng=3)
    coms = mask.pixels[::7]
    con = comcore.geometry.contacts(mask, pushes)
    agree, total = 0, 0
    for i, action in enumerate(pushes):
        direction = action[2:] - action[:2]
        for mu in (0.2, 1.0):
            theta = MODEL.predict_hypotheses(mask, action[None], coms, mu)[:, 0, 0]
            sense = comcore.vt.predicted_sense(
                coms, con.point[i], con.normal[i], direction, mu, band=3.0
            )
            decided = sense != 0
            agree += int((np.sign(theta[decided]) == sense[decided]).sum())
            total += int(decided.sum())
    assert total > 200
    assert agree / total >= 0.97


def test_outputs_are_finite_for_every_pixel_and_friction():
    mask = notched()
    pushes = comcore.sample_pushes(mask, 3, cone=0.5, rng=1)
    model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    for mu in (0.0, 0.5, np.inf):
        out = model.predict_hypotheses(mask, pushes, mask.pixels, mu)
        assert out.shape == (mask.area_px, 3, 3)
        assert np.isfinite(out).all()


def test_interpolation_is_exact_at_the_lattice_nodes():
    mask = notched()
    push = comcore.sample_pushes(mask, 1, rng=2)
    lattice = PushLattice(mask, push[0], 0.01)
    nodes = lattice.points[mask.contains(lattice.points)][::3]
    grid = comcore.LimitSurfaceModel(pusher_radius=0.004, node_spacing=0.01)
    direct = comcore.LimitSurfaceModel(pusher_radius=0.004, node_spacing=0.0)
    table = pressure_table(mask, ("tilted", 32), lambda m, p: direct._pressures(m, p))
    # The nodes' pressures come from the per-mask table: the same pressures, directly.
    expected = direct._motions(mask, push, table_pressures(table, nodes, 2.0), 0.4)
    asked = np.vstack([nodes, mask.pixels])  # many hypotheses: the lattice is used
    got = grid.predict_hypotheses(mask, push, asked, 0.4)[: len(nodes)]
    np.testing.assert_allclose(got, expected, atol=1e-5)  # single-precision solves


def test_lattice_is_fine_near_the_push_line():
    lattice = PushLattice(notched(), np.array([0.0, 30.0, 20.0, 30.0]), 0.01)  # 4 px
    steps = np.diff(lattice.lever)
    near = np.abs(lattice.lever[:-1] + steps / 2) < 2
    assert steps[near].max() <= 1.5 and np.isclose(steps.max(), 4.0)
    assert np.isclose(lattice.lever, 0).any()  # a node line on the push line


def test_a_push_that_misses_gives_no_motion():
    out = MODEL.predict_hypotheses(plate(), [(0, 2, 40, 2)], [(24.5, 19.5)], 0.5)
    np.testing.assert_array_equal(out, 0.0)


def test_empty_inputs_give_empty_outputs():
    no_push = MODEL.predict_hypotheses(plate(), np.zeros((0, 4)), [(24.5, 19.5)], 0.5)
    no_com = MODEL.predict_hypotheses(plate(), [(0, 19.5, 24, 19.5)], np.zeros((0, 2)), 0.5)
    assert no_push.shape == (1, 0, 3)
    assert no_com.shape == (0, 1, 3)


def test_implements_the_predictor_protocol():
    assert isinstance(MODEL, comcore.Predictor)


@pytest.mark.parametrize(
    ("mu", "error", "match"),
    [(-0.1, ValueError, "mu must be >= 0"), (float("nan"), ValueError, "mu must be finite"),
     ("0.3", TypeError, "mu must be a number"), (None, TypeError, "mu must be a number")],
)  # fmt: skip
def test_bad_friction_is_refused(mu, error, match):
    with pytest.raises(error, match=match):
        MODEL.predict_hypotheses(plate(), [(0, 19.5, 24, 19.5)], [(24.5, 19.5)], mu)


def test_a_push_starting_inside_is_refused():
    with pytest.raises(ValueError, match="start outside the object"):
        MODEL.predict_hypotheses(plate(), [(20, 19.5, 44, 19.5)], [(24.5, 19.5)], 0.5)


def test_bad_coms_are_refused():
    with pytest.raises(ValueError, match="coms"):
        MODEL.predict_hypotheses(plate(), [(0, 19.5, 24, 19.5)], [(1.0, 2.0, 3.0)], 0.5)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [({"pusher_radius": -0.001}, ValueError, "pusher_radius must be >= 0"),
     ({"pusher_radius": "4 mm"}, TypeError, "pusher_radius must be a number"),
     ({"pressure": "uniform"}, ValueError, "pressure must be one of"),
     ({"n_steps": 0}, ValueError, "n_steps must be an integer >= 1"),
     ({"n_steps": 2.5}, TypeError, "n_steps must be an integer"),
     ({"support_points": 3}, ValueError, "support_points must be an integer >= 4"),
     ({"node_spacing": -1.0}, ValueError, "node_spacing must be >= 0")],
)  # fmt: skip
def test_bad_settings_are_refused(kwargs, error, match):
    with pytest.raises(error, match=match):
        comcore.LimitSurfaceModel(**kwargs)


def test_does_not_mutate_its_inputs():
    coms = np.array([[24.5, 15.0], [30.0, 25.0]])
    actions = np.array([[0.0, 19.5, 24.0, 19.5]])
    before = coms.copy(), actions.copy()
    MODEL.predict_hypotheses(plate(), actions, coms, 0.5)
    np.testing.assert_array_equal(coms, before[0])
    np.testing.assert_array_equal(actions, before[1])


def _first_push_calls(monkeypatch, hint: bool):
    """Integration batches and motions of a first push asked about three frictions in turn."""
    import comcore.motion._limit_surface as module

    calls = []
    real = module.push_motions
    monkeypatch.setattr(module, "push_motions", lambda *a, **k: calls.append(1) or real(*a, **k))
    mask, model = plate(), comcore.LimitSurfaceModel(pusher_radius=0.004)
    mus, coms = (1.5, 0.6, 0.1), mask.pixels  # many CoMs: interpolated from lattice nodes
    if hint:
        model.expect_frictions(mask, mus)
    action = [(0.0, 19.5, 24.0, 19.5)]
    out = [model.predict_hypotheses(mask, action, coms, mu) for mu in mus]
    return len(calls), np.stack(out)


def test_told_the_frictions_the_first_push_is_one_batch_with_the_same_motions(monkeypatch):
    batches, hinted = _first_push_calls(monkeypatch, hint=True)
    unhinted_batches, plain = _first_push_calls(monkeypatch, hint=False)
    assert (batches, unhinted_batches) == (1, 3)
    # The solves run in single precision, in batches of another size: rounding only.
    np.testing.assert_allclose(hinted, plain, rtol=0, atol=1e-6)
    assert np.abs(hinted).max() > 0.01  # the push moves the plate


@pytest.mark.parametrize("spacing", [0.01, 0.0])
def test_path_hypotheses_start_at_rest_and_end_at_the_push(spacing):
    """predict_path_hypotheses: fraction 0 is no motion, 1 the push's own; in [0, 1] only."""
    mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 10))
    model = comcore.LimitSurfaceModel(pusher_radius=0.004, node_spacing=spacing)
    action = (0.0, 19.0, 30.0, 19.0)
    coms = [(24.5, 15.0), (20.0, 24.0)]
    path = model.predict_path_hypotheses(mask, action, coms, 0.5, [0.0, 0.5, 1.0])
    end = model.predict_hypotheses(mask, [action], coms, 0.5)[:, 0]
    assert path.shape == (2, 3, 3)
    assert np.abs(path[:, 0]).max() == 0.0
    np.testing.assert_allclose(path[:, 2], end, atol=1e-12)
    assert 0 < abs(path[0, 1, 0]) < abs(path[0, 2, 0])  # it turns on the way
    with pytest.raises(ValueError, match="fractions must lie in"):
        model.predict_path_hypotheses(mask, action, coms, 0.5, [0.5, 1.5])
    with pytest.raises(ValueError, match="fractions must lie in"):
        model.predict_path_hypotheses(mask, action, coms, 0.5, [np.nan])

"""Tests of the bagged posterior of a recording (comcore/active/_posterior.py, estimate_posterior's region)."""

import numpy as np
import pytest

import comcore
from comcore.active._grid import GridPosterior
from comcore.active._posterior import PushLikelihoods
from tests.active.test_blocking import ToyModel, _plate, _robot

#: No floor: the bagging alone.
NO_FLOOR = comcore.Likelihood(systematic_error=0.0)


def _two_groups(separation: float, n: int = 24):
    """Pushes of one plate, every other one made as if its CoM were ``separation`` px off.

    What a model that errs differently on pushes made from different places does to
    a recording: the pushes agree within each group and disagree across.
    """
    mask = _plate()
    a, b = (20.0, 15.0), (20.0 + separation, 15.0)
    actions = comcore.sample_pushes(mask, n, rng=5)
    robots = _robot(mask, a, 0.3), _robot(mask, b, 0.3)
    motions = [robots[i % 2](comcore.Action(*x)) for i, x in enumerate(actions)]
    return mask, actions, motions, a, b


@pytest.mark.parametrize("separation", [3.0, 6.0])
def test_pushes_that_disagree_widen_the_region_over_both(separation):
    mask, actions, motions, a, b = _two_groups(separation)
    kw = {"model": ToyModel(), "likelihood": NO_FLOOR}
    plain = comcore.estimate_posterior(mask, actions, motions, bootstrap=0, **kw)
    bagged = comcore.estimate_posterior(mask, actions, motions, **kw)
    # the posterior of all 24 pushes is sure of a CoM between the two, and misses one
    assert plain.status == "ok" and not (plain.region_holds(a) and plain.region_holds(b))
    # the bagged region holds both, the estimate is the posterior's mean all the same
    assert bagged.region_holds(a) and bagged.region_holds(b)
    assert bagged.com == plain.com
    np.testing.assert_array_equal(bagged.posterior.image, plain.posterior.image)
    assert bagged.posterior.bootstrap == 200 and plain.posterior.bootstrap == 0
    # the covariance is the bagged spread about the estimate: wider than the posterior's
    assert np.trace(bagged.covariance) > 1.2 * np.trace(plain.covariance)


def test_pushes_that_agree_leave_the_region_about_as_it_is():
    mask, actions, motions, a, _ = _two_groups(0.0)
    kw = {"model": ToyModel(), "likelihood": NO_FLOOR}
    plain = comcore.estimate_posterior(mask, actions, motions, bootstrap=0, **kw)
    bagged = comcore.estimate_posterior(mask, actions, motions, **kw)
    radii = [e.posterior.credible_radius_px for e in (plain, bagged)]
    assert plain.region_holds(a) and bagged.region_holds(a)
    # at most sqrt(2) wider (twice the variance where the model is right); here 7 %
    assert radii[0] <= radii[1] <= 1.2 * radii[0]


def test_the_region_is_seeded_and_the_seed_matters_little():
    mask, actions, motions, *_ = _two_groups(4.0)
    kw = {"model": ToyModel(), "likelihood": NO_FLOOR}
    one = comcore.estimate_posterior(mask, actions, motions, rng=1, **kw)
    again = comcore.estimate_posterior(mask, actions, motions, rng=1, **kw)
    np.testing.assert_array_equal(one.region, again.region)
    radii = [
        comcore.estimate_posterior(mask, actions, motions, rng=seed, **kw).posterior.credible_radius_px
        for seed in range(4)
    ]
    assert np.ptp(radii) < 0.1 * np.mean(radii)
    generator = comcore.estimate_posterior(
        mask, actions, motions, rng=np.random.default_rng(1), **kw
    )
    np.testing.assert_array_equal(generator.region, one.region)


def test_one_push_is_its_own_bag():
    mask, actions, motions, *_ = _two_groups(0.0, n=1)
    kw = {"model": ToyModel(), "likelihood": NO_FLOOR}
    plain = comcore.estimate_posterior(mask, actions, motions, bootstrap=0, **kw)
    bagged = comcore.estimate_posterior(mask, actions, motions, **kw)
    np.testing.assert_array_equal(plain.region, bagged.region)
    assert bagged.posterior.bootstrap == 0


def test_the_bag_of_equal_weights_is_the_posterior_tempers_and_pruning_included():
    """Every resampling weighted 1 per push gives the posterior back (the mixture of tempers)."""
    mask = _plate()
    pixels, prior = mask.pixels, np.full(mask.area_px, 1.0 / mask.area_px)
    rng = np.random.default_rng(0)
    post = GridPosterior(pixels, prior, mus=[0.2, 0.5], n_models=1, n_tempers=2)
    kept = PushLikelihoods(post, n_pushes=3)
    for _ in range(3):
        full = rng.normal(size=post.log_w.shape) * 3
        full[rng.random(len(pixels)) < 0.2] = -np.inf  # pruned hypotheses
        tempered = np.stack([0.5 * full, full])
        post.update(tempered, full)
        kept.add(tempered)
    assert len(kept.live) < post.log_w.size  # the pruned ones are dropped

    class Ones:
        def standard_exponential(self, shape):
            return np.ones(shape)

    bagged = kept.bagged_marginal(post.temper_weights, 5, Ones())
    np.testing.assert_allclose(bagged, post.marginal, atol=1e-12)


def test_credible_level_reads_what_the_region_was_read_from():
    mask, actions, motions, *_ = _two_groups(6.0)
    est = comcore.estimate_posterior(mask, actions, motions, model=ToyModel(), likelihood=NO_FLOOR)
    inside = np.argwhere(est.region)  # (row, col)
    levels = [comcore.credible_level(est, (c, r)) for r, c in inside]
    assert max(levels) < 0.9 + 1e-9  # every pixel of the 90 % region is below level 0.9
    outside = np.argwhere(mask.data & ~est.region)
    assert min(comcore.credible_level(est, (c, r)) for r, c in outside) >= 0.9 - 1e-9


@pytest.mark.parametrize(
    ("bootstrap", "rng", "error", "match"),
    [
        (-1, 0, ValueError, "bootstrap must be >= 0"),
        (2.5, 0, TypeError, "bootstrap must be an int"),
        (True, 0, TypeError, "bootstrap must be an int"),
        (10**6, 0, ValueError, "bootstrap must be at most 10000"),
        (200, -3, ValueError, "rng must be None"),
        (200, "seed", TypeError, "rng must be None"),
    ],
)
def test_bad_bootstrap_or_rng_is_refused_by_name(bootstrap, rng, error, match):
    mask, actions, motions, *_ = _two_groups(0.0, n=3)
    with pytest.raises(error, match=match):
        comcore.estimate_posterior(mask, actions, motions, model=None, bootstrap=bootstrap, rng=rng)


def test_the_callers_arrays_are_not_mutated():
    mask, actions, motions, *_ = _two_groups(3.0, n=6)
    actions = np.array(actions, dtype=float)
    motions = np.array(motions, dtype=float)
    before = actions.copy(), motions.copy()
    comcore.estimate_posterior(mask, actions, motions, model=ToyModel())
    np.testing.assert_array_equal(actions, before[0])
    np.testing.assert_array_equal(motions, before[1])


def test_a_bag_too_big_to_keep_is_refused_before_any_push_is_scored(monkeypatch):
    import comcore.active._posterior as bagging

    mask, actions, motions, *_ = _two_groups(0.0, n=6)
    monkeypatch.setattr(bagging, "MAX_KEPT_FLOATS", 6 * mask.area_px * 6 - 1)  # 6 friction values
    with pytest.raises(ValueError, match="bootstrap would keep .* pass bootstrap=0"):
        comcore.estimate_posterior(mask, actions, motions, model=None)
    est = comcore.estimate_posterior(mask, actions, motions, model=None, bootstrap=0)
    assert est.posterior.bootstrap == 0


def test_the_bagging_benchmark_runs():
    pytest.importorskip("trimesh")  # the simulators
    from tests.scripts import run_script

    out = run_script(
        "benchmarks/timing/bench_bagging.py", "--objects", "Obj1", "--pushes", "4", "--repeats", "1",
        "--model", "none", timeout=120,
    )  # fmt: skip
    row = [line for line in out.splitlines() if line.startswith("| Obj1 | 4 |")]
    assert len(row) == 1 and row[0].endswith(" s |")


def test_a_session_takes_no_bootstrap():
    mask = _plate()
    with pytest.raises(TypeError, match="unexpected keyword argument 'bootstrap'"):
        comcore.ActiveSession(mask, model=None, bootstrap=10)
    with pytest.raises(TypeError, match="unexpected keyword argument 'bootstrap'"):
        comcore.estimate_active(mask, _robot(mask, (20.0, 15.0), 0.3), model=None, bootstrap=10)

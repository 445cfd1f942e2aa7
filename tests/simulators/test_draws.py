"""What the simulator accepts: a random simulator redrawn while refused, pushes redrawn too."""

import numpy as np
import pytest

pytest.importorskip("shapely")
pytest.importorskip("trimesh")

import comcore
import simulators

BOWTIE = [(0, 0), (0.05, 0.05), (0.05, 0), (0, 0.05)]  # self-intersecting: refused


def same_draw(a, b):
    return a.com_m == b.com_m and a.mu_contact == b.mu_contact and a.shape.name == b.shape.name


# -- accepted_random_simulator ------------------------------------------------------------
@pytest.mark.parametrize("rng", [7, [7, 0]])
def test_a_draw_accepted_at_once_is_random_simulators(rng):
    sim = simulators.accepted_random_simulator("Obj5", "high", rng=rng)
    assert same_draw(sim, simulators.random_simulator("Obj5", "high", rng=rng))
    per_attempt = simulators.accepted_random_simulator("Obj5", "high", rng=lambda k: [7, k])
    assert same_draw(per_attempt, simulators.random_simulator("Obj5", "high", rng=[7, 0]))


def test_a_refused_draw_is_redrawn_and_reported():
    seen = []

    def shape(attempt):
        vertices = BOWTIE if attempt == 0 else simulators.load_object("Obj2").vertices_m
        return simulators.ObjectShape.from_vertices(vertices, name="drawn")

    sim = simulators.accepted_random_simulator(
        shape, rng=lambda k: [3, k], on_refusal=lambda k, e: seen.append((k, type(e)))
    )
    assert seen == [(0, ValueError)]
    expected = simulators.random_simulator(shape(1), rng=[3, 1])  # the second attempt's stream
    assert same_draw(sim, expected)


def test_redraws_continue_one_stream():
    rng, again = np.random.default_rng(4), np.random.default_rng(4)
    calls = []

    def shape(attempt):
        calls.append(attempt)
        if attempt == 0:
            again.random()  # what the refused attempt takes from the stream ...
            rng.random()
            raise ValueError("refused")
        return simulators.load_object("Obj1")

    sim = simulators.accepted_random_simulator(shape, rng=rng)
    assert calls == [0, 1]
    assert same_draw(sim, simulators.random_simulator("Obj1", rng=again))  # ... is not redrawn


def test_every_draw_refused_is_one_error_with_the_last_reason():
    seen = []
    with pytest.raises(RuntimeError, match="no random simulator accepted in 3 attempt") as info:
        simulators.accepted_random_simulator(
            "Obj1", rng=0, attempts=3, resolution=-1.0, on_refusal=lambda k, e: seen.append(k)
        )
    assert seen == [0, 1, 2]
    assert "resolution must be a finite number > 0" in str(info.value)
    assert isinstance(info.value.__cause__, ValueError)


@pytest.mark.parametrize(("attempts", "error"), [(0, ValueError), (2.0, TypeError)])
def test_bad_attempts(attempts, error):
    with pytest.raises(error, match="attempts must be"):
        simulators.accepted_random_simulator("Obj1", rng=0, attempts=attempts)


# -- sample_accepted_pushes --------------------------------------------------------------
@pytest.fixture(scope="module")
def sim():
    return simulators.random_simulator("Obj9", "low", rng=0)  # a U: concave


def refusing(sim, calls):
    """``push_motions``, refusing (like the simulator) any batch with a start left of x = 60."""

    def respond(pushes):
        calls.append(len(pushes))
        if (pushes[:, 0] < 60).any():
            raise ValueError("action(s) start inside the object")
        return sim.push_motions(pushes)

    return respond


def test_pushes_nothing_refuses_are_the_samplers_with_their_motions(sim):
    found = simulators.sample_accepted_pushes(sim, 8, cone=0.3, rng=5)
    drawn = comcore.sample_pushes(sim.mask, 8, cone=0.3, rng=5)
    assert np.array_equal(found.pushes, drawn) and found.refused == 0
    assert np.array_equal(found.motions, sim.push_motions(drawn))


@pytest.mark.parametrize("batched", [True, False])
def test_refused_pushes_are_replaced_by_fresh_draws_of_the_same_stream(sim, batched):
    calls = []
    found = simulators.sample_accepted_pushes(
        sim, 10, cone=0.3, rng=1, respond=refusing(sim, calls), batched=batched
    )
    rng, kept, refused = np.random.default_rng(1), [], 0
    while len(kept) < 10:  # the same draws, by hand
        batch = comcore.sample_pushes(sim.mask, 10 - len(kept), cone=0.3, rng=rng)
        kept += [p for p in batch if p[0] >= 60]
        refused += int((batch[:, 0] < 60).sum())
    assert refused > 0 and found.refused == refused
    assert np.array_equal(found.pushes, np.array(kept))
    assert np.allclose(found.motions, sim.push_motions(found.pushes), rtol=0, atol=1e-9)
    assert (max(calls) > 1) == batched  # one push at a time unless batched


def test_one_push_at_a_time_gives_the_single_push_motions(sim):
    found = simulators.sample_accepted_pushes(sim, 4, cone=0.3, rng=2, batched=False)
    single = np.array([sim.push(p).motion for p in found.pushes])
    assert np.array_equal(found.motions, single)


def test_too_many_refusals_are_an_error(sim):
    def refuse(pushes):
        raise ValueError("no")

    with pytest.raises(RuntimeError, match="refused 12 pushes: 0 of 4 accepted in 3 rounds"):
        simulators.sample_accepted_pushes(sim, 4, rng=0, respond=refuse, draws=3)


def test_no_pushes_and_bad_counts(sim):
    found = simulators.sample_accepted_pushes(sim, 0, rng=0)
    assert found.pushes.shape == (0, 4) and found.motions.shape == (0, 3)
    with pytest.raises(ValueError, match="n must be >= 0"):
        simulators.sample_accepted_pushes(sim, -1)
    with pytest.raises(TypeError, match="n must be an integer"):
        simulators.sample_accepted_pushes(sim, 2.0)

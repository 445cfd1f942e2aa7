"""Tests of predictors.anp: the attentive neural process (tiny models only)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import comcore

torch = pytest.importorskip("torch")

from predictors.anp import (  # noqa: E402
    DEFAULT_WEIGHTS,
    AnpConfig,
    AnpModel,
    AnpPredictor,
    load_weights,
    save_weights,
)
from predictors.anp import data as anp_data  # noqa: E402
from predictors.anp.features import (  # noqa: E402
    N_PUSH_FEATURES,
    dihedral,
    motions_from_targets,
    object_frame,
    push_features,
    targets_from_motions,
)
from predictors.anp.shapes import polygon_area, random_polygon, rasterise  # noqa: E402
from predictors.anp.train import evaluate, main, train_epoch  # noqa: E402

TINY = AnpConfig(image_size=16, channels=(4, 8), width=16, heads=2, latent=4)
TINY_ARGS = ["--source", "toy", "--pushes", "8", "--batch", "8", "--width", "16",
             "--channels", "4", "8"]  # fmt: skip


@pytest.fixture(autouse=True, scope="module")
def one_thread():
    """Tiny models run fastest on one thread (and the test machine is shared)."""
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(threads)


def tiny_predictor(seed=0) -> AnpPredictor:
    torch.manual_seed(seed)
    return AnpPredictor(model=AnpModel(TINY))


@pytest.fixture(scope="module")
def scene():
    img = np.zeros((40, 50), bool)
    img[8:30, 10:42] = True
    img[8:16, 30:42] = False  # an L: no symmetry
    mask = comcore.Mask(img, resolution=0.0025)
    pushes = comcore.sample_pushes(mask, 20, cone=0.4, rng=1)
    com = np.add(mask.centroid, (2.0, 1.5))
    motions = anp_data.toy_motions(mask, pushes, com, 0.3)
    priors = [(comcore.Action(*a), comcore.Motion(*m)) for a, m in zip(pushes[:8], motions[:8])]
    return mask, pushes[8:], priors


@pytest.fixture(scope="module")
def toy_features():
    episodes = anp_data.load_or_generate(64, seed=3, n_pushes=8, source="toy")
    return anp_data.featurise(episodes, image_size=16)


# -- import hygiene ---------------------------------------------------------------------
def test_importing_comcore_and_predictors_does_not_import_torch():
    code = "import sys, comcore, predictors; assert 'torch' not in sys.modules, 'torch'"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_missing_torch_says_which_extra_to_install():
    code = (
        "import sys; sys.modules['torch'] = None\n"
        "try:\n    from predictors import AnpPredictor\n"
        "except ImportError as e:\n"
        "    assert 'pip install comcore[anp]' in str(e), e\n"
        "    assert e.__cause__ is not None\n    print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True)
    assert out.stdout.strip() == "ok"


# -- predictor --------------------------------------------------------------------------
def test_shapes_and_protocol(scene):
    mask, queries, priors = scene
    anp = tiny_predictor()
    # few-shot only: Alg. 1/2's predict_motions takes it; the estimators need a CoM input
    assert not isinstance(anp, comcore.Predictor)
    with pytest.raises(TypeError, match="only the few-shot predict"):
        comcore.motion.check_predictor(anp)
    assert comcore.motion.predict_motions(anp, mask, queries, priors).shape == (12, 3)
    mean, var = anp.predict_distribution(mask, queries, priors, n_samples=4, rng=0)
    assert mean.shape == var.shape == (12, 3) and (var > 0).all()
    assert anp.predict(mask, queries[:1]).shape == (1, 3)  # zero priors
    assert anp.predict(mask, np.zeros((0, 4))).shape == (0, 3)


def test_prediction_is_the_mean_at_the_latent_mean_and_sampling_is_seeded(scene):
    mask, queries, priors = scene
    anp = tiny_predictor()
    mean, _ = anp.predict_distribution(mask, queries, priors)
    np.testing.assert_array_equal(anp.predict(mask, queries, priors), mean)
    a = anp.predict_distribution(mask, queries, priors, n_samples=3, rng=7)
    b = anp.predict_distribution(mask, queries, priors, n_samples=3, rng=7)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_permutation_of_priors_does_not_change_predictions(scene):
    mask, queries, priors = scene
    anp = tiny_predictor()
    order = np.random.default_rng(0).permutation(len(priors))
    shuffled = [priors[i] for i in order]
    np.testing.assert_allclose(
        anp.predict(mask, queries, shuffled), anp.predict(mask, queries, priors), atol=1e-5
    )


def test_priors_change_predictions(scene):
    mask, queries, priors = scene
    anp = tiny_predictor()
    assert not np.allclose(anp.predict(mask, queries, priors), anp.predict(mask, queries))


def test_pushes_that_miss_predict_no_motion(scene):
    mask, _, priors = scene
    miss = np.array([[0.0, 1.0, 5.0, 1.0]])
    mean, var = tiny_predictor().predict_distribution(mask, miss, priors)
    np.testing.assert_array_equal(mean, 0.0)
    assert (var > 0).all()


def test_bad_input_is_named(scene):
    mask, queries, _ = scene
    anp = tiny_predictor()
    with pytest.raises(TypeError, match=r"mask must be a comcore\.Mask"):
        anp.predict(mask.data, queries)
    with pytest.raises(ValueError, match=r"actions must have shape \(n, 4\)"):
        anp.predict(mask, queries[:, :3])
    with pytest.raises(ValueError, match=r"priors\[0\] must be an \(Action, Motion\) pair"):
        anp.predict(mask, queries, [(1, 2)])
    with pytest.raises(ValueError, match="n_samples must be an int >= 0"):
        anp.predict_distribution(mask, queries, n_samples=-1)
    with pytest.raises(TypeError, match="model must be an AnpModel"):
        AnpPredictor(model=object())
    with pytest.raises(ValueError, match="threads must be None or an int >= 1"):
        AnpPredictor(model=AnpModel(TINY), threads=0)


@pytest.mark.parametrize(("rng", "error"), [(-1, ValueError), ("a", TypeError)])
def test_a_bad_rng_is_named(scene, rng, error):
    mask, queries, priors = scene
    with pytest.raises(error, match="rng must be None, a non-negative int seed"):
        tiny_predictor().predict_distribution(mask, queries, priors, n_samples=2, rng=rng)
    with pytest.raises(error, match="rng must be None, a non-negative int seed"):
        random_polygon(rng)


def test_thread_setting_is_restored(scene):
    mask, queries, priors = scene
    before = torch.get_num_threads()
    anp = AnpPredictor(model=AnpModel(TINY), threads=before + 1)
    anp.predict(mask, queries, priors)
    assert torch.get_num_threads() == before


def test_cost_is_linear_in_the_number_of_priors():
    from torch.utils.flop_counter import FlopCounterMode

    model = AnpModel(TINY).eval()

    def flops(k, q=6):
        with FlopCounterMode(display=False) as counter, torch.no_grad():
            model(torch.rand(1, 16, 16), torch.zeros(1), torch.rand(1, k, N_PUSH_FEATURES),
                  torch.rand(1, k, 3), torch.rand(1, q, N_PUSH_FEATURES))  # fmt: skip
        return counter.get_total_flops(), counter.get_flop_counts()["Global"]

    counts = [flops(k)[0] for k in range(0, 25, 4)]
    steps = np.diff(counts)
    assert steps[0] > 0 and (steps == steps[0]).all(), counts  # exactly affine in k
    # the attention itself is counted (as bmm) and grows with queries x priors
    assert any("bmm" in str(op) for op in flops(4)[1])
    assert flops(8, q=12)[0] - flops(4, q=12)[0] > flops(8, q=6)[0] - flops(4, q=6)[0]


# -- weights files ------------------------------------------------------------------------
def test_save_load_round_trip(tmp_path, scene):
    mask, queries, priors = scene
    anp = tiny_predictor(seed=3)
    path = save_weights(anp.model, tmp_path / "w.pt", meta={"note": "test"})
    raw = torch.load(path, weights_only=True)
    assert raw["format"] == "comcore-anp" and raw["config"]["width"] == 16
    loaded = AnpPredictor(weights=path)
    assert loaded.config == TINY and loaded.meta == {"note": "test"}
    np.testing.assert_array_equal(
        loaded.predict(mask, queries, priors), anp.predict(mask, queries, priors)
    )


def test_bad_weights_files_raise_clear_errors(tmp_path):
    junk = tmp_path / "junk.pt"
    junk.write_bytes(b"not a torch file")
    with pytest.raises(ValueError, match="is not a comcore ANP weights file"):
        AnpPredictor(weights=junk)
    other = tmp_path / "other.pt"
    torch.save({"weights": torch.zeros(3)}, other)
    with pytest.raises(ValueError, match="is not a comcore ANP weights file"):
        load_weights(other)
    path = save_weights(AnpModel(TINY), tmp_path / "w.pt")
    payload = torch.load(path, weights_only=True)
    payload["config"]["width"] = 32  # parameters no longer fit the config
    torch.save(payload, path)
    with pytest.raises(ValueError, match="does not match the ANP model"):
        AnpPredictor(weights=path)
    payload["config"] = {"depth": 3}
    torch.save(payload, path)
    with pytest.raises(ValueError, match="bad config: config has unknown keys"):
        AnpPredictor(weights=path)
    with pytest.raises(FileNotFoundError, match="does not exist"):
        AnpPredictor(weights=tmp_path / "missing.pt")


def test_shipped_weights_load_and_are_documented():
    anp = AnpPredictor()
    record = json.loads(DEFAULT_WEIGHTS.with_suffix(".json").read_text())
    for key in ("command", "date", "train_episodes", "train_seconds", "validation", "sha256"):
        assert key in record
    assert anp.config.to_dict() == record["config"]
    assert DEFAULT_WEIGHTS.stat().st_size < 5_000_000


def shipped_copy(tmp_path):
    import shutil

    pt, record = tmp_path / "anp.pt", tmp_path / "anp.json"
    shutil.copyfile(DEFAULT_WEIGHTS, pt)
    shutil.copyfile(DEFAULT_WEIGHTS.with_suffix(".json"), record)
    return pt, record


def test_a_flipped_bit_in_the_weights_is_refused(tmp_path):
    # One flipped bit used to load silently and predict 4e34.
    pt, _ = shipped_copy(tmp_path)
    assert load_weights(pt)[0].config == AnpPredictor().config  # the intact copy loads
    data = bytearray(pt.read_bytes())
    data[len(data) // 2] ^= 0x40
    pt.write_bytes(bytes(data))
    with pytest.raises(
        ValueError, match=r"has SHA-256 [0-9a-f]{64}, but [0-9a-f]{64} was recorded"
    ):
        AnpPredictor(weights=pt)
    with pytest.raises(ValueError, match="was recorded: the file is corrupt"):
        load_weights(DEFAULT_WEIGHTS, sha256="0" * 64)


def exponent_bit_flipped(tmp_path, name: str, index: int = 0):
    """A copy of the shipped weights, WITHOUT their training record, with one bit flipped.

    The bit is the top exponent bit of element ``index`` of the parameter ``name``, found
    in the file's raw bytes (torch stores tensors uncompressed): a value below 1 in
    magnitude becomes about 2**128 times larger, still finite.
    """
    state = load_weights(DEFAULT_WEIGHTS)[0].state_dict()
    raw = state[name].numpy().tobytes()
    data = bytearray(DEFAULT_WEIGHTS.read_bytes())
    assert data.count(raw) == 1
    assert abs(float(state[name].view(-1)[index])) < 1.0
    data[data.find(raw) + 4 * index + 3] ^= 0x40  # float32, little-endian: bit 30
    path = tmp_path / "anp.pt"
    path.write_bytes(bytes(data))
    assert not path.with_suffix(".json").exists()  # nothing to check the file against
    return path


def test_weights_with_one_exponent_bit_flipped_predict_no_impossible_motion(tmp_path, scene):
    # The user's case: a corrupt weights file without a training record beside it loads
    # (its values stay finite) and its theta for every push was about 1e36 rad, which
    # flowed into the estimators. The output layer's first bias (theta's mean) here.
    mask, pushes, priors = scene
    path = exponent_bit_flipped(tmp_path, "decoder.4.bias")
    anp = AnpPredictor(weights=path)  # loads: there is no record to check it against
    message = r"AnpPredictor \(weights '.*anp.pt'\) predicted a motion no push can cause: .* rad, more than half a turn"
    with pytest.raises(ValueError, match=message):
        anp.predict(mask, pushes, priors)
    with pytest.raises(ValueError, match=message):  # where predictions enter the core
        comcore.motion.predict_motions(anp, mask, pushes, priors)
    assert np.abs(AnpPredictor().predict(mask, pushes, priors)[:, 0]).max() < np.pi


def test_weights_that_overflow_inside_the_network_are_named(tmp_path, scene):
    # A flipped bit early in the network overflows inside it; torch then refuses a
    # distribution's parameters deep inside. The error names the predictor and weights.
    mask, pushes, priors = scene
    anp = AnpPredictor(weights=exponent_bit_flipped(tmp_path, "push.0.bias"))
    with pytest.raises(ValueError, match=r"AnpPredictor \(weights '.*anp.pt'\) failed inside the network .*the weights are broken"):
        anp.predict(mask, pushes, priors)


def test_a_malformed_record_is_refused(tmp_path):
    pt, record = shipped_copy(tmp_path)
    record.write_text(json.dumps({"sha256": "abc"}))
    with pytest.raises(ValueError, match="malformed sha256: 'abc'"):
        load_weights(pt)


def test_the_shipped_weights_need_a_recorded_hash(tmp_path, monkeypatch):
    import predictors.anp.predictor as anp_predictor

    pt, record = shipped_copy(tmp_path)
    record.write_text("{}")
    monkeypatch.setattr(anp_predictor, "DEFAULT_WEIGHTS", pt.resolve())
    with pytest.raises(ValueError, match="shipped weights' record .* has no sha256"):
        load_weights(pt)


def test_non_finite_weights_are_refused(tmp_path):
    # An inf weight used to predict inf.
    model = AnpModel(TINY)
    with torch.no_grad():
        model.decoder[0].weight[0, 0] = float("inf")
    path = save_weights(model, tmp_path / "w.pt")
    with pytest.raises(ValueError, match=r"non-finite values \(NaN or inf\) in 'decoder.0.weight'"):
        load_weights(path)
    with pytest.raises(ValueError, match="model holds non-finite values"):
        AnpPredictor(model=model)


@pytest.mark.parametrize(
    ("config", "match"),
    [
        ({"width": 10, "heads": 4}, "width 10 must be divisible by heads 4"),
        ({"channels": [12]}, "channels must be multiples of 8 .or below 8., got 12"),
        ({"image_size": 0}, "image_size must be an int >= 1, got 0"),
        ({"latent": 1.5}, "latent must be an int >= 1, got 1.5"),
        ({"channels": []}, "channels must be a non-empty tuple"),
        ({"channels": 4}, "channels must be a list of ints"),
        ({"heads": True}, "heads must be an int >= 1, got True"),
    ],
)
def test_impossible_configs_are_refused(tmp_path, config, match):
    with pytest.raises(ValueError, match=match):
        AnpConfig.from_dict(config)
    path = save_weights(AnpModel(TINY), tmp_path / "w.pt")
    payload = torch.load(path, weights_only=True)
    payload["config"] = config
    torch.save(payload, path)
    with pytest.raises(ValueError, match="bad config: config " + match):
        load_weights(path)


def test_the_com_from_the_shape_alone_needs_no_priors(scene):
    # AnpPredictor().estimate_com(mask) crashed in encode_pushes (zero pushes to reshape).
    mask, _, priors = scene
    anp = tiny_predictor()
    com = anp.estimate_com(mask)
    assert len(com) == 2 and np.isfinite(com).all()
    assert com != anp.estimate_com(mask, priors)


def test_priors_no_push_can_cause_are_refused_not_turned_into_a_com_off_the_image():
    # The fuzzing reproducer: three pushes on a 24 x 16 rectangle with the motion
    # (-0.1, -1e12, 1e12) put the shipped model's CoM at (-7.7e10, 9.9e10) px. Zero rotation
    # everywhere, identical actions or all-zero motions stay on the object.
    anp = AnpPredictor()
    mask = comcore.Mask(np.pad(np.ones((24, 16), bool), 12))
    pushes = comcore.sample_pushes(mask, 6, rng=0)

    def priors(motion, actions=pushes[:3]):
        return [(comcore.Action(*a), comcore.Motion(*motion)) for a in actions]

    for motion, actions in [((0.0, 8, 0), pushes[:3]), ((0.0, 0, 0), pushes[:3]),
                            ((0.1, 8, 0), [pushes[0]] * 3)]:  # fmt: skip
        assert mask.contains([anp.estimate_com(mask, priors(motion, actions))])[0]
    for call in (anp.estimate_com, lambda m, p: anp.predict(m, pushes[3:], p)):
        with pytest.raises(ValueError, match=r"priors\[0\] moves the object 1\.414e\+12 px, more "
                                             r"than 10 times its push's length \(16\.8 px\)"):
            call(mask, priors((-0.1, -1e12, 1e12)))
        with pytest.raises(ValueError, match=r"priors\[0\] turns the object by 4 rad"):
            call(mask, priors((4.0, 1, 0)))


def test_a_com_far_outside_the_object_is_refused(scene, monkeypatch):
    # The backstop behind the priors' check: a latent outside the training range
    mask, _, priors = scene
    anp = tiny_predictor()
    monkeypatch.setattr(anp.model, "com", lambda z: torch.full((z.shape[0], 2), 1e9))
    with pytest.raises(ValueError, match=r"AnpPredictor \(a model given in code\) put the CoM "
                                         r"at \(.*\) px, .* px outside the object's bounding box"):
        anp.estimate_com(mask, priors)


# -- frame, features, symmetries ------------------------------------------------------------
def test_frame_round_trip_and_object_in_unit_disc(scene):
    mask = scene[0]
    frame = object_frame(mask, 32)
    u = frame.to_frame(mask.pixels)
    assert np.hypot(u[:, 0], u[:, 1]).max() < 1.0
    motions = np.array([[0.1, 3.0, -2.0], [-0.3, 0.0, 7.5]])
    back = motions_from_targets(targets_from_motions(motions, frame.length_px), frame.length_px)
    np.testing.assert_allclose(back, motions, rtol=1e-6)


@pytest.mark.parametrize("flip", [False, True])
def test_dihedral_matches_transforming_the_scene_in_pixels(scene, flip):
    """Rotating/mirroring the mask in pixels and re-featurising == dihedral() in the frame."""
    mask, queries, _ = scene
    motions = np.random.default_rng(0).normal(size=(len(queries), 3))
    frame = object_frame(mask, 16)
    feats = push_features(mask, frame, queries)
    targs = targets_from_motions(motions, frame.length_px)
    data, acts, mots = mask.data, queries.copy(), motions.copy()
    if flip:  # (x, y) -> (W - 1 - x, y): a mirror reverses rotation
        data = data[:, ::-1]
        acts[:, [0, 2]] = data.shape[1] - 1 - acts[:, [0, 2]]
        mots[:, :2] = -mots[:, :2]
    data = np.rot90(data)  # (x, y) -> (y, W - 1 - x): a quarter turn CCW on screen
    acts = np.column_stack([acts[:, 1], mask.shape[1] - 1 - acts[:, 0],
                            acts[:, 3], mask.shape[1] - 1 - acts[:, 2]])  # fmt: skip
    mots = np.column_stack([mots[:, 0], mots[:, 2], -mots[:, 1]])
    point = np.array([20.0, 12.0])  # e.g. the CoM, moved like the actions' start points
    turned = comcore.Mask(data, mask.resolution)
    point2 = np.array([point[1], mask.shape[1] - 1 - (
        mask.shape[1] - 1 - point[0] if flip else point[0])])  # fmt: skip
    frame2 = object_frame(turned, 16)
    image, f2, t2, p2 = dihedral(
        frame.image, feats, targs, k=1, flip=flip, points=frame.to_frame(point)
    )
    np.testing.assert_allclose(p2, frame2.to_frame(point2), atol=1e-6)
    np.testing.assert_allclose(image, frame2.image, atol=1e-5)
    np.testing.assert_allclose(f2, push_features(turned, frame2, acts), atol=1e-4)
    np.testing.assert_allclose(t2, targets_from_motions(mots, frame2.length_px), atol=1e-5)


def test_random_polygons_are_seeded_simple_and_sized():
    for seed in range(12):
        v = random_polygon(seed)
        np.testing.assert_array_equal(v, random_polygon(seed))
        area = polygon_area(v)
        assert 0.0020 <= area <= 0.0170
        # a simple polygon's raster has the polygon's area (self-crossings lose area)
        assert rasterise(v, 0.001).sum() * 1e-6 == pytest.approx(area, rel=0.05)


# -- data and training -----------------------------------------------------------------------
def test_cache_is_reused_and_episodes_depend_on_seed_and_index_only(tmp_path, monkeypatch):
    first = anp_data.load_or_generate(3, seed=5, n_pushes=6, source="toy", cache=tmp_path)
    direct = anp_data.make_episode(5, 2, 6, source="toy")
    np.testing.assert_array_equal(first.motions[2], direct[3])
    monkeypatch.setattr(anp_data, "make_episode", lambda *a, **k: pytest.fail("re-simulated"))
    again = anp_data.load_or_generate(3, seed=5, n_pushes=6, source="toy", cache=tmp_path)
    np.testing.assert_array_equal(first.motions, again.motions)
    assert all((a == b).all() for a, b in zip(first.masks, again.masks))


def test_a_small_training_run_lowers_the_loss(toy_features):
    torch.manual_seed(0)
    model = AnpModel(TINY)
    before = evaluate(model, toy_features, n_priors=4)["loss"]
    optimizer = torch.optim.Adam(model.parameters(), lr=3e-3)
    for epoch in range(6):
        train_epoch(model, optimizer, toy_features, epoch=epoch, seed=0, batch=8, max_priors=4)
    after = evaluate(model, toy_features, n_priors=4)["loss"]
    assert after < before - 0.5, (before, after)


def test_training_is_deterministic_and_resumable(tmp_path, monkeypatch):
    import predictors.anp.train as train_module

    cache = tmp_path / "cache"
    common = [*TINY_ARGS, "--episodes", "16", "--val-episodes", "8", "--cache", str(cache),
              "--epochs", "2"]  # fmt: skip
    full = main([*common, "--out", str(tmp_path / "a.pt")])
    calls = []

    def interrupted(*args, **kwargs):  # the run dies at the start of its second epoch
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return original(*args, **kwargs)

    original = train_module.train_epoch
    monkeypatch.setattr(train_module, "train_epoch", interrupted)
    with pytest.raises(KeyboardInterrupt):
        main([*common, "--out", str(tmp_path / "b.pt")])
    monkeypatch.setattr(train_module, "train_epoch", original)
    with pytest.raises(ValueError, match="was written by a run with other arguments"):
        main([*common[:-1], "3", "--out", str(tmp_path / "b.pt"), "--resume"])
    resumed = main([*common, "--out", str(tmp_path / "b.pt"), "--resume"])
    assert [h["train_loss"] for h in resumed["history"]] == [
        h["train_loss"] for h in full["history"]
    ]
    a, _ = load_weights(tmp_path / "a.pt")
    b, _ = load_weights(tmp_path / "b.pt")
    for (name, pa), pb in zip(a.state_dict().items(), b.state_dict().values()):
        assert torch.equal(pa, pb), name
    record = json.loads((tmp_path / "a.json").read_text())
    assert record["train_episodes"] == 16 and "loss" in record["validation"]


def test_out_defaults_to_the_current_directory_and_peak_memory_is_recorded(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    shipped = DEFAULT_WEIGHTS.stat().st_mtime_ns
    record = main([*TINY_ARGS, "--episodes", "8", "--val-episodes", "8", "--epochs", "1"])
    assert (tmp_path / "anp.pt").is_file() and (tmp_path / "anp.json").is_file()
    assert DEFAULT_WEIGHTS.stat().st_mtime_ns == shipped
    assert set(record["peak_rss_mib"]) == {"self", "children"}
    assert record["peak_rss_mib"]["self"] > 10  # torch alone is more than 10 MiB
    assert json.loads((tmp_path / "anp.json").read_text())["peak_rss_mib"] == record["peak_rss_mib"]


def test_missing_tqdm_says_which_extras_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    with pytest.raises(ImportError, match=r"pip install comcore\[anp,sim\]") as e:
        anp_data.progress_bar(total=1)
    assert e.value.__cause__ is not None


def test_training_on_the_simulator_without_it_says_which_extras_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "simulators", None)
    with pytest.raises(ImportError, match=r"--source sim\) needs the simulator: pip install "
                       r"comcore\[anp,sim\]"):  # fmt: skip
        main(["--source", "sim", "--episodes", "8", "--cache", str(tmp_path), "--out",
              str(tmp_path / "a.pt")])  # fmt: skip
    assert not (tmp_path / "a.pt").exists()


def test_benchmark_says_how_to_install_the_anp(monkeypatch):
    from comcore.bench import PREDICTORS, _registry

    def no_torch(name):
        raise ImportError("No module named 'torch'")

    monkeypatch.setattr(_registry.importlib, "import_module", no_torch)
    reason = PREDICTORS["anp"].requires()
    assert reason == (
        "predictors.AnpPredictor is not available (ImportError: No module named 'torch'); "
        "pip install comcore[anp]"
    )
    monkeypatch.undo()
    assert PREDICTORS["anp"].requires() is None


def test_simulated_episodes_are_seeded_and_in_comcore_conventions():
    pytest.importorskip("pymunk")
    mask_data, resolution, actions, motions, com, mu = anp_data.make_episode(11, 1, 4)
    again = anp_data.make_episode(11, 1, 4)
    np.testing.assert_array_equal(motions, again[3])
    assert actions.shape == (4, 4) and motions.shape == (4, 3) and 0.5 <= mu <= 0.9
    mask = comcore.Mask(mask_data, resolution)
    assert mask.contains([com])[0]
    assert comcore.geometry.contacts(mask, actions).hit.all()
    # the pushes move the centroid forward, along the push
    direction = actions[:, 2:] - actions[:, :2]
    assert (np.einsum("ij,ij->i", motions[:, 1:], direction) > 0).all()


def test_benchmark_evaluation_reports_per_trial_metrics():
    pytest.importorskip("pymunk")
    from predictors.anp.evaluate import evaluate_on_benchmark

    rows = evaluate_on_benchmark(tiny_predictor(), ["Obj3"], n_priors=3, n_queries=4)
    assert [(r["object"], r["friction"]) for r in rows] == [("Obj3", "low"), ("Obj3", "high")]
    assert all(0 <= r["sense_acc"] <= 1 or r["n_sense"] == 0 for r in rows)
    assert all(r["theta_mae_deg"] >= 0 and r["t_mae_mm"] > 0 for r in rows)

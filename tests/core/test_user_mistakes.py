"""A user's mistake never ends in a confident wrong answer.

One test per mistake a user can make with the inputs (those with the camera's frame are
tests/camera/test_image.py's), and the rest of a fuzzing pass not tested elsewhere: each
reproduces what the user did and shows the clear error, the status that is not ``ok`` or
the result that works.
"""

from __future__ import annotations

import json
import math
import tracemalloc

import numpy as np
import pytest

import comcore
from comcore.cli import main

#: The user's object: an L drawn as a camera image (uint8, dark on a bright table), and its
#: true CoM in pixels. At 5 mm per pixel so that the default model's posterior takes a second.
RESOLUTION = 0.005
TRUE_COM = (16.0, 29.0)


def l_image() -> np.ndarray:
    img = np.full((46, 50), 200, np.uint8)
    img[8:38, 8:18] = 40
    img[28:38, 8:40] = 40
    return img


@pytest.fixture(scope="module")
def recording():
    """Pushes on the L and their motions from the user's own model (not comcore's default).

    The user's model: the exact limit surface with the pressure peaked at the CoM (the
    estimator's default weighs the tilted one) and contact friction 0.4.
    """
    mask = comcore.mask_from_image(l_image(), resolution=RESOLUTION)
    actions = comcore.sample_pushes(mask, 8, cone=0.3, rng=1)
    user_model = comcore.LimitSurfaceModel(pusher_radius=0.004, pressure="peaked")
    motions = user_model.predict_hypotheses(mask, actions, [TRUE_COM], 0.4)[0]
    return mask, actions, motions


def write_files(tmp_path, actions, motions):
    from matplotlib.image import imsave

    image = tmp_path / "object.png"
    imsave(image, l_image(), cmap="gray", vmin=0, vmax=255)
    pushes = tmp_path / "pushes.csv"
    rows = [",".join(f"{v:.6g}" for v in (*a, *m)) for a, m in zip(actions, motions)]
    pushes.write_text("sx,sy,ex,ey,theta,tx,ty\n" + "\n".join(rows) + "\n")
    return image, pushes


def cli(capsys, image, pushes, *extra):
    code = main(["estimate", "--mask", str(image), "--pushes", str(pushes), "--resolution",
                 str(RESOLUTION), "--json", "--no-overlay", *extra])  # fmt: skip
    out = capsys.readouterr()
    return code, (json.loads(out.out) if out.out else None), out.err


# -- theta with the y-up sign --------------------------------------------------------------


def test_theta_with_the_y_up_sign_is_inconsistent_with_the_default_model(recording):
    mask, actions, motions = recording
    honest = comcore.estimate_posterior(mask, actions, motions)
    # consistent; eight pushes leave a 90 % region (10 mm) wider than the 6 mm target
    assert honest.status == "wide" and honest.error_px(TRUE_COM) < 3
    flipped = comcore.estimate_posterior(mask, actions, motions * [-1, 1, 1])
    assert flipped.status == "inconsistent"


def test_theta_with_the_y_up_sign_is_not_ok_with_the_voting_theorem_alone():
    # The senses alone tell the mistake when the pushes' lines do not all pass near the
    # centroid (then a CoM mirrored through it would explain the flipped senses): here 16
    # pushes on the L at 2.5 mm per pixel, with the user's model. The CLI says which mistake
    # it is with any method (test_the_cli_says_theta_looks_sign_flipped).
    mask = comcore.mask_from_image(np.kron(l_image(), np.ones((2, 2), np.uint8)),
                                   resolution=RESOLUTION / 2)  # fmt: skip
    actions = comcore.sample_pushes(mask, 16, cone=0.3, rng=1)
    user_model = comcore.LimitSurfaceModel(pusher_radius=0.004, pressure="peaked")
    motions = user_model.predict_hypotheses(mask, actions, [(32.5, 58.5)], 0.4)[0]
    # consistent; the senses alone leave a region (30 mm) wider than the 6 mm target
    assert comcore.estimate_posterior(mask, actions, motions, model=None).status == "wide"
    est = comcore.estimate_posterior(mask, actions, motions * [-1, 1, 1], model=None)
    senses = est.posterior.senses
    assert est.status == "inconsistent"
    assert senses.fewest_unexplained > 3 * senses.expected and senses.p_value < 1e-3


def test_most_pushes_contradicting_the_answer_is_never_ok():
    # ten pushes, five saying the CoM is above row 8 and five below row 18 of a square:
    # whatever the CoM, half of them contradict it; the excess surprise alone let it pass
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4))
    actions = [(0, 8, 30, 8), (0, 18, 30, 18)] * 5
    est = comcore.estimate_posterior(mask, actions, [(0.2, 3, 0), (-0.2, 3, 0)] * 5, model=None)
    assert est.posterior.excess_nats < comcore.active._likelihood.consistency_threshold(10)
    assert est.status == "inconsistent" and est.posterior.senses.fewest_unexplained == 5


@pytest.mark.parametrize("extra", [(), ("--model", "none"), ("--method", "alg2")])
def test_the_cli_says_theta_looks_sign_flipped(tmp_path, capsys, recording, extra):
    pytest.importorskip("matplotlib")
    _, actions, motions = recording
    image, pushes = write_files(tmp_path, actions, motions)
    code, result, err = cli(capsys, image, pushes, *extra)
    # consistent; eight pushes leave a region wider than the 6 mm target: usable, no warning
    assert code == 0 and result["status"] == "wide" and result["mistake"] is None and err == ""
    image, pushes = write_files(tmp_path, actions, motions * [-1, 1, 1])
    code, result, err = cli(capsys, image, pushes, *extra)
    assert code == 3 and result["status"] == "inconsistent"  # not to be used: exit code 3
    assert "every theta's sign flipped" in result["mistake"]
    assert "warning: status inconsistent: the pushes are explained far better" in err


def test_alg2_on_a_sign_flipped_recording_is_not_ok(recording):
    mask, actions, motions = recording
    # consistent, its final region (30 mm) wider than the 6 mm target; flipped: contradicted
    assert comcore.estimate_progressive(mask, actions, motions).status == "wide"
    assert comcore.estimate_progressive(mask, actions, motions * [-1, 1, 1]).status == "inconsistent"


# -- x and y swapped in the pushes CSV -----------------------------------------------------


def test_x_and_y_swapped_in_the_csv_is_refused_with_the_hint(tmp_path, capsys, recording):
    pytest.importorskip("matplotlib")
    _, actions, motions = recording
    image, pushes = write_files(tmp_path, actions[:, [1, 0, 3, 2]], motions[:, [0, 2, 1]])
    code, result, err = cli(capsys, image, pushes)
    assert code == 2 and result is None
    assert "pushes miss the object or start inside it" in err
    assert "with the x and y columns swapped 8 of 8 would hit it" in err


# -- a resolution in the wrong unit --------------------------------------------------------


def test_a_resolution_ten_times_too_small_shows_in_the_object_size(tmp_path, capsys, recording):
    # 10 times too small is still a plausible camera (0.5 mm per pixel): the pushes are in
    # pixels and cannot tell; the object's size in metres, printed first, shows it.
    pytest.importorskip("matplotlib")
    _, actions, motions = recording
    image, pushes = write_files(tmp_path, actions, motions)
    args = ["estimate", "--mask", str(image), "--pushes", str(pushes), "--no-overlay",
            "--model", "none", "--resolution"]  # fmt: skip
    assert main([*args, str(RESOLUTION)]) == 0
    assert "object: 16.0 x 15.0 cm at 0.005 m per pixel" in capsys.readouterr().out
    assert main([*args, str(RESOLUTION / 10)]) == 0
    assert "object: 1.6 x 1.5 cm at 0.0005 m per pixel" in capsys.readouterr().out


def test_millimetres_typed_as_metres_are_refused_before_anything_is_allocated():
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=r"resolution 2\.5 m per pixel is implausible .*"
                           r"did you mean millimetres, 0\.0025\?"):  # fmt: skip
            comcore.mask_from_image(l_image(), resolution=2.5)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 5e6  # bytes: the 36 GiB lattice is never reached


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda m: comcore.Mask(m.data, resolution=0.25), r"did you mean centimetres, 0\.0025\?"),
        (lambda m: comcore.ActiveSession(m, pusher_radius=5), r"pusher_radius 5 m .* 0\.005\?"),
        (lambda m: comcore.LimitSurfaceModel(pusher_radius=5), r"pusher_radius 5 m"),
        (lambda m: comcore.estimate_posterior(m, [(0, 33, 12, 33)], [(0.1, 1, 0)],
                                              pusher_radius=4), r"pusher_radius 4 m"),
        (lambda m: comcore.estimate_active(m, lambda a: (0.1, 0, 0), pusher_radius=4),
         r"pusher_radius 4 m"),
        (lambda m: comcore.PushChoice(travel=30), r"travel 30 m .* millimetres, 0\.03\?"),
        (lambda m: comcore.StopRule(target_radius=6), r"target_radius 6 m .* 0\.006\?"),
        (lambda m: comcore.Likelihood(pusher_error=3), r"pusher_error 3 m .* 0\.003\?"),
        (lambda m: comcore.Likelihood(motion_noise=(0.5, 0.5)), r"motion_noise's translation"),
        (lambda m: comcore.Likelihood(motion_noise=(5.0, 0.0005)), r"did you mean degrees"),
        (lambda m: comcore.Likelihood(translation_error=(1.0, 0.05)), r"translation_error's"),
    ],
)
def test_lengths_implausible_in_metres_are_refused_with_a_guess_at_the_unit(make, match):
    mask = comcore.mask_from_image(l_image(), resolution=RESOLUTION)
    with pytest.raises(ValueError, match=match):
        make(mask)


def test_theta_in_degrees_is_refused(tmp_path, capsys, recording):
    mask, actions, motions = recording
    degrees = motions * [180 / math.pi, 1, 1]
    with pytest.raises(ValueError, match=r"motions\[\d\] turns the object by .* rad, more than pi"):
        comcore.estimate_posterior(mask, actions, degrees, model=None)
    session = comcore.ActiveSession(mask, model=None, rng=0)
    session.next_push()
    with pytest.raises(ValueError, match=r"motion\[0\] turns the object by 30 rad.* degrees"):
        session.observe(motion=(30.0, 2.0, 0.0))
    pytest.importorskip("matplotlib")
    image, pushes = write_files(tmp_path, actions, degrees)
    code, _, err = cli(capsys, image, pushes, "--method", "alg2")
    assert code == 2 and "column theta: " in err and "theta must be in radians (degrees?" in err


def test_the_cli_refuses_a_pusher_radius_in_millimetres(tmp_path, capsys, recording):
    pytest.importorskip("matplotlib")
    _, actions, motions = recording
    image, pushes = write_files(tmp_path, actions, motions)
    code, result, err = cli(capsys, image, pushes, "--pusher-radius", "4")
    assert code == 2 and result is None
    assert "--pusher-radius 4 m is implausible" in err and "millimetres, 0.004?" in err


def test_a_push_under_a_pixel_is_refused_with_its_numbers():
    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4), resolution=0.0025)
    model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    with pytest.raises(ValueError, match=r"actions\[1\] is 0\.012 px long \(3e-05 m at 0\.0025"):
        model.predict_hypotheses(mask, [(0, 13, 30, 13), (3.0, 13, 3.012, 13)], [(13, 13)], 0.3)


def test_a_session_whose_pushes_would_be_under_a_pixel_is_refused_before_any_push():
    # 5 cm per pixel is a believable camera, but its 3 cm pushes are 0.6 px: nothing to see
    mask = comcore.Mask(np.pad(np.ones((6, 8), bool), 3), resolution=0.05)
    with pytest.raises(ValueError, match=r"candidates\[0\] is 0\.836 px long \(0\.0418 m at 0\.05"):
        comcore.ActiveSession(mask, rng=0)


def test_a_lattice_over_the_memory_bound_is_refused_with_the_push(monkeypatch):
    from comcore.motion import _lattice as _push_lattice

    mask = comcore.Mask(np.pad(np.ones((20, 20), bool), 4), resolution=0.0025)
    lattice = _push_lattice.PushLattice(mask, np.array([0.0, 13.0, 30.0, 13.0]), 0.01)
    monkeypatch.setattr(_push_lattice, "MAX_LATTICE_NODES", len(lattice.points) - 1)
    with pytest.raises(ValueError, match=r"the push \[0\.0, 13\.0, 30\.0, 13\.0\] needs a lattice"
                       r" of .* nodes \(node spacing 4 px = 0\.01 m at 0\.0025 m per pixel"):  # fmt: skip
        _push_lattice.PushLattice(mask, np.array([0.0, 13.0, 30.0, 13.0]), 0.01)
    fine = comcore.LimitSurfaceModel(pusher_radius=0.004, node_spacing=1e-6)  # 0.4 micrometre
    monkeypatch.undo()
    with pytest.raises(ValueError, match="over the bound of 1,000,000"):
        fine.predict_hypotheses(mask, [(0, 13, 30, 13)], [(13.0, 13.0), (14.0, 12.0)], 0.3)


# -- a mask that is not the object ---------------------------------------------------------


def _session_waiting():
    mask = comcore.mask_from_image(l_image(), resolution=RESOLUTION)
    session = comcore.ActiveSession(mask, model=None, rng=0)
    return mask, session, session.next_push()


@pytest.mark.parametrize("foreign", ["one pixel", "another object"])
def test_observe_refuses_a_mask_that_is_not_the_object(foreign):
    mask, session, action = _session_waiting()
    if foreign == "one pixel":
        data = np.zeros(mask.shape, bool)
        data[20, 20] = True
        match = r"mask is not the first mask's object moved: its area is 1 px"
    else:  # a disc of the L's area where the L was
        yy, xx = np.mgrid[: mask.shape[0], : mask.shape[1]]
        cx, cy = mask.centroid
        data = np.hypot(xx - cx, yy - cy) <= math.sqrt(mask.area_px / math.pi)
        match = r"mask is not the first mask's object moved: .* px \(RMS\) from the first"
    history = session.history
    with pytest.raises(ValueError, match=match):
        session.observe(comcore.Mask(data, resolution=RESOLUTION))
    assert session.status == "waiting_observation" and session.next_push() == action
    assert session.history == history and session.pushes == ()
    session.observe(failed=True)  # the session goes on
    assert session.pushes[0].outcome == "failed" and not session.done


def test_observe_takes_the_object_moved():
    mask, session, _ = _session_waiting()
    moved = comcore.Mask(np.roll(mask.data, (1, 2), axis=(0, 1)), resolution=RESOLUTION)
    session.observe(moved)
    assert session.pushes[0].outcome == "evidence"
    assert session.pose.tx == pytest.approx(2.0, abs=0.05)


# -- the rest of the fuzzing pass ----------------------------------------------------------


def test_n_mu_past_what_runs_in_30_seconds_is_refused():
    with pytest.raises(ValueError, match=r"n_mu must be at most 32 \(friction values"):
        comcore.Likelihood(n_mu=1000)
    with pytest.raises(ValueError, match=r"n_candidates must be at most 20000"):
        comcore.PushChoice(n_candidates=10**6)


@pytest.mark.parametrize("name", ["big300", "two_blobs"])
def test_one_metre_per_pixel_is_refused_before_any_allocation(name):
    image = np.zeros((320, 320), bool)
    if name == "big300":
        image[10:310, 10:310] = True
    else:
        image[20:60, 20:60] = image[200:260, 150:300] = True
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=r"resolution 1 m per pixel is implausible"):
            comcore.Mask(image, resolution=1.0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 5e6


def _floats(value):
    """Every float inside records, named tuples, dicts, tuples and arrays."""
    if isinstance(value, float):
        yield value
    elif isinstance(value, np.ndarray) and value.dtype.kind == "f":
        yield from value.ravel().tolist()
    elif isinstance(value, dict):
        for v in value.values():
            yield from _floats(v)
    elif isinstance(value, (tuple, list)):
        for v in value:
            yield from _floats(v)
    elif hasattr(value, "__dataclass_fields__"):
        for name in value.__dataclass_fields__:
            yield from _floats(getattr(value, name))


def test_a_motion_given_rather_than_measured_shows_no_nan():
    mask, session, _ = _session_waiting()
    session.observe(motion=(0.05, 2.0, 1.0))
    est = session.estimate()
    assert est.pushes[0].residual_px is None
    offline = comcore.estimate_posterior(mask, pushes=est.pushes, model=None)
    for value in (est, offline):
        assert not any(math.isnan(v) for v in _floats(value.posterior))
        assert not any(math.isnan(v) for v in _floats(value.pushes))


def test_the_refusal_benchmark_script_runs():
    pytest.importorskip("shapely")
    from tests.scripts import run_script

    out = run_script("benchmarks/accuracy/observe_refusal.py", "--seed", "1", "--objects", "Obj1,Obj7",
                     "--pushes", "1", timeout=120).splitlines()  # fmt: skip
    assert out[0].startswith("seed 1, mask_noise 0.5, 2 objects")
    assert "refused 0 (0.0 %)" in out[1]
    assert out[2] == "another object: refused 2 of 2 (100.0 %)"
    assert out[3] == "a single pixel: refused 2 of 2 (100.0 %)"


# -- a mask that is not one solid object ---------------------------------------------------


def _not_one_object(name: str) -> np.ndarray:
    if name == "two_blobs":
        image = np.zeros((40, 60), bool)
        image[5:25, 5:20] = image[10:26, 35:50] = True
    elif name == "ring":
        image = np.pad(np.ones((24, 24), bool), 6)
        image[12:24, 12:24] = False
    elif name == "line":
        image = np.zeros((30, 30), bool)
        image[15, 3:27] = True
    elif name == "2x2":
        image = np.zeros((12, 12), bool)
        image[5:7, 5:7] = True
    else:  # checkerboard: one 8-connected part, every other pixel a hole
        image = np.pad(np.indices((20, 20)).sum(axis=0) % 2 == 0, 4)
    return image


ONE_OBJECT_REFUSALS = {
    "two_blobs": r"mask has 2 separate parts \(areas 300 and 240 px\): pass one object's mask, "
    r"e\.g\. comcore\.Mask\(comcore\.geometry\.largest_component\(mask\.data\)",
    "ring": r"mask has holes of 144 px, 25 % of the object's 576 px \(at most 1 % allowed\)",
    "line": r"mask is nowhere 3 pixels across \(24 px in all",
    "2x2": r"mask is nowhere 3 pixels across \(4 px in all",
    "checkerboard": r"mask has holes of 162 px",
}


def _run_estimator(estimator: str, mask: comcore.Mask):
    y = mask.centroid[1]
    acts, mots = [(-5.0, y, 70.0, y), (-5.0, y + 2, 70.0, y + 2)], [(0.2, 2, 0), (0.2, 2, 0)]
    if estimator == "heatmap":
        return comcore.estimate_heatmap(mask, acts, mots)
    if estimator == "progressive":
        return comcore.estimate_progressive(mask, acts, mots)
    if estimator == "posterior":
        return comcore.estimate_posterior(mask, acts, mots, model=None)
    if estimator == "session":
        return comcore.ActiveSession(mask, model=None, rng=0)
    return comcore.estimate_active(mask, lambda action: comcore.Motion(0.1, 0, 0), model=None,
                                   stop=comcore.StopRule(max_pushes=2), rng=0)  # fmt: skip


@pytest.mark.parametrize("estimator", ["heatmap", "progressive", "posterior", "session", "active"])
@pytest.mark.parametrize("name", list(ONE_OBJECT_REFUSALS))
def test_a_mask_that_is_not_one_solid_object_is_refused(name, estimator):
    # Refused, not flagged: Alg. 2 said "ok" on the line and the 2 x 2 speck with exact
    # senses, and on two blobs or a ring its region cannot hold a CoM between the parts
    mask = comcore.Mask(_not_one_object(name))
    with pytest.raises(ValueError, match=ONE_OBJECT_REFUSALS[name]):
        _run_estimator(estimator, mask)


def test_a_mask_with_small_holes_from_segmentation_noise_is_accepted():
    # holes up to comcore._validation.MAX_HOLE_SHARE (1 %) of the filled area pass as they are
    image = np.pad(np.ones((40, 40), bool), 5)
    image[20:22, 20:22] = image[30, 12] = False  # 5 px of 1600: 0.31 %
    acts = [(0, 25.3, 50, 25.3), (25.3, 0, 25.3, 50)]
    est = comcore.estimate_progressive(comcore.Mask(image), acts, [(0.2, 2, 0), (-0.2, 0, 2)])
    assert est.status == "wide"  # accepted and consistent; two cuts leave a quarter of the plate
    image[10:14, 30:34] = False  # 16 px more: 21 of 1600, 1.3 %
    with pytest.raises(ValueError, match=r"mask has holes of 21 px, 1\.31 % of the object's "
                                         r"1600 px \(at most 1 % allowed\)"):  # fmt: skip
        comcore.estimate_progressive(comcore.Mask(image), acts, [(0.2, 2, 0), (-0.2, 0, 2)])


# -- sample_pushes: a count typed for a seed, a travel too short --------------------------


def test_sample_pushes_refuses_more_than_its_maximum_at_once():
    # n=74638432 ran past 30 s
    mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 10))
    with pytest.raises(ValueError, match=r"n must be at most 100000 pushes \(MAX_SAMPLED_PUSHES"):
        comcore.sample_pushes(mask, 74638432)
    assert comcore.geometry._sampling.MAX_SAMPLED_PUSHES == 100_000


@pytest.mark.parametrize("travel", [5e-324, 1e-6, 0.0006])
def test_sample_pushes_refuses_a_travel_under_a_quarter_pixel(travel):
    # travel=5e-324 returned pushes that end before the object's outline: they miss it
    mask = comcore.Mask(np.pad(np.ones((30, 30), bool), 10), resolution=0.0025)
    with pytest.raises(ValueError, match=r"travel must carry the pusher at least 0\.25 pixel "
                       r"past the contact, 0\.000625 m at this mask's resolution, got .* m "
                       r"\(travel is in metres\)"):  # fmt: skip
        comcore.sample_pushes(mask, 5, travel=travel, rng=0)
    pushes = comcore.sample_pushes(mask, 200, cone=0.5, travel=0.000625, rng=0)  # the minimum
    assert comcore.geometry.contacts(mask, pushes).hit.all()
    with pytest.raises(ValueError, match=r"travel 30 m is implausible.*millimetres, 0\.03"):
        comcore.sample_pushes(mask, 5, travel=30, rng=0)


# -- the simulator's construction ----------------------------------------------------------
SQUARE_M = [(0, 0), (0.08, 0), (0.08, 0.06), (0, 0.06)]


@pytest.mark.parametrize(("options", "match"), [
    ({"margin": 7239}, r"margin 7239 m and resolution 0\.0025 m per pixel make a camera image "
                       r"of 5791224 x 5791232 pixels .* more than MAX_IMAGE_PIXELS \(16777216\): "
                       r"margin and resolution are in metres"),
    ({"resolution": 1e-6}, r"margin 0\.02 m and resolution 1e-06 m per pixel make a camera "
                           r"image of 100000 x 120000 pixels"),
])  # fmt: skip
def test_a_simulator_camera_image_too_large_is_refused_before_any_allocation(options, match):
    # margin=7239 asked numpy for 488 TiB (a MemoryError from inside numpy)
    simulators = pytest.importorskip("simulators")
    pytest.importorskip("shapely")
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match=match):
            simulators.PushSimulator.from_polygon(SQUARE_M, **options).mask  # noqa: B018
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 20e6


@pytest.mark.parametrize(("options", "error", "match"), [
    ({"com": "ab"}, TypeError, r"com must be two finite numbers \(metres\), got str"),
    ({"com": object()}, TypeError, r"com must be two finite numbers \(metres\), got <object"),
    ({"point_masses": "abc"}, TypeError, r"point_masses must be a sequence of \(x, y, m\) rows "
                                         r"\(metres, kg\), got str"),
    ({"point_masses": [(0.01, 0.01)]}, ValueError, r"point_masses must be a sequence of "
                                                   r"\(x, y, m\) rows .*got shape \(1, 2\)"),
    ({"point_masses": [(0.01, 0.01, 1.0), (1.0,)]}, TypeError, r"point_masses must be a "
                                                              r"sequence of \(x, y, m\) rows"),
    ({"point_masses": 5}, TypeError, r"point_masses must be a sequence .*, got int"),
    ({"density_gradient": "ab"}, TypeError, r"density_gradient must be two finite numbers "
                                            r"\(per metre\), got str"),
    ({"density_gradient": object()}, TypeError, r"density_gradient must be two finite numbers"),
])  # fmt: skip
def test_a_simulator_mass_given_wrong_is_refused_by_name(options, error, match):
    simulators = pytest.importorskip("simulators")
    pytest.importorskip("shapely")
    with pytest.raises(error, match=match):
        simulators.PushSimulator.from_polygon(SQUARE_M, **options)


@pytest.mark.parametrize(("options", "error", "match"), [
    ({"quasi_static_ratio": "a"}, TypeError, r"quasi_static_ratio must be a number, got str"),
    ({"quasi_static_ratio": None}, TypeError, r"quasi_static_ratio must be a number, got None"),
    ({"step_m": "a"}, TypeError, r"step_m must be a number, got str"),
    ({"projections": 2.0}, TypeError, r"projections must be an integer, got float"),
    ({"iterations": 10**12}, ValueError, r"iterations must be an integer from 1 to 1000 "
                                         r"\(MAX_STEP_COUNT\), got 1000000000000"),
    ({"settle_steps": -1}, ValueError, r"settle_steps must be an integer from 0 to 1000"),
    ({"engine": ["pymunk"]}, ValueError, r"engine must be one of \('quasistatic', 'pymunk'\)"),
])  # fmt: skip
def test_engine_settings_given_wrong_are_refused_by_name(options, error, match):
    simulators = pytest.importorskip("simulators")
    with pytest.raises(error, match=match):
        simulators.EngineSettings(**options)
    # numpy numbers are numbers: the same settings as Python's
    assert simulators.EngineSettings(step_m=np.float32(0.0005), iterations=np.int64(5)) == (
        simulators.EngineSettings(step_m=float(np.float32(0.0005)), iterations=5)
    )


# -- pixel_centres on odd images -----------------------------------------------------------
@pytest.mark.parametrize(("image", "error", "match"), [
    ([], ValueError, r"image must be a 2-D \(H, W\) boolean image, got 1-D shape \(0,\)"),
    ([1, 0, 1], ValueError, r"image must be a 2-D \(H, W\) boolean image, got 1-D shape \(3,\)"),
    (np.ones((2, 2, 2), bool), ValueError, r"image must be a 2-D .* got 3-D shape \(2, 2, 2\)"),
    (5, ValueError, r"image must be a 2-D \(H, W\) boolean image, got 0-D shape \(\)"),
    (np.zeros((0, 4), bool), ValueError, r"image must not be empty, got shape \(0, 4\)"),
    (np.array([[0, 255]], np.uint8), ValueError, r"image must hold booleans \(or 0 and 1\), got "
                                                 r"the value 255: threshold a grey-level image"),
    (np.array([[np.nan, 1.0]]), ValueError, r"image must hold booleans .* got the value nan"),
    (np.array([[None, 1]], dtype=object), TypeError, r"image must be a 2-D .* got dtype object"),
    ([[1], [0, 1]], TypeError, r"image must be a 2-D \(H, W\) boolean image, got ragged rows"),
    ("ab", TypeError, r"image must be a 2-D \(H, W\) boolean image, got str"),
    (None, TypeError, r"image must be a 2-D \(H, W\) boolean image, got NoneType"),
    (np.array([["a"]]), TypeError, r"image must be a 2-D \(H, W\) boolean image, got dtype <U1"),
])  # fmt: skip
def test_pixel_centres_names_its_argument_on_odd_images(image, error, match):
    with pytest.raises(error, match=match):
        comcore.conventions.pixel_centres(image)


def test_pixel_centres_takes_bool_like_images_and_not_a_mask():
    want = [[1.0, 0.0], [0.0, 1.0]]
    for image in ([[False, True], [True, False]], [[0, 1], [1, 0]], np.eye(2)[::-1]):
        assert comcore.conventions.pixel_centres(image).tolist() == want
    with pytest.raises(TypeError, match=r"got a Mask: pass its \.data"):
        comcore.conventions.pixel_centres(comcore.Mask(np.ones((3, 3), bool)))

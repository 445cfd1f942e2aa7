import numpy as np
import pytest

import comcore
from tests.extras import require_simulators

# A drawn example: an arrow pointing right (+x) on screen.
ARROW = np.array(
    [
        "........",
        "....#...",
        "....##..",
        "#######.",
        "....##..",
        "....#...",
        "........",
        "........",
    ]
)


def drawn(rows):
    return np.array([[ch == "#" for ch in row] for row in rows])


def points_of(img):
    r, c = np.nonzero(img)
    return np.column_stack([c, r]).astype(float)


def image_of(points, shape):
    img = np.zeros(shape, bool)
    p = np.rint(points).astype(int)
    img[p[:, 1], p[:, 0]] = True
    return img


def test_quarter_turn_ccw_matches_rot90_on_screen():
    # np.rot90 turns an image counter-clockwise as displayed (row 0 on top).
    img = drawn(ARROW)
    center = (3.5, 3.5)  # the centre of the 8 x 8 image
    moved = comcore.apply_motion(points_of(img), np.pi / 2, (0.0, 0.0), center)
    assert np.array_equal(image_of(moved, img.shape), np.rot90(img))


def test_the_arrow_points_up_the_screen_after_a_positive_quarter_turn():
    img = drawn(ARROW)
    moved = comcore.apply_motion(points_of(img), np.pi / 2, (0.0, 0.0), (3.5, 3.5))
    tip_before = points_of(img)[np.argmax(points_of(img)[:, 0])]
    tip_after = moved[np.argmin(moved[:, 1])]  # the smallest row is the top of the screen
    assert tuple(tip_before) == (6.0, 3.0)
    # 2.5 px right of the centre becomes 2.5 px above it (smaller row).
    assert tip_after == pytest.approx((3.0, 1.0))


def test_translation_is_applied_after_rotation():
    out = comcore.apply_motion([[1.0, 0.0]], np.pi, (2.0, 3.0), (0.0, 0.0))
    assert np.allclose(out, [[1.0, 3.0]])


def test_rotation_matrix_is_a_rotation_and_composes():
    a, b = 0.3, -1.1
    ra, rb = comcore.conventions.rotation_matrix(a), comcore.conventions.rotation_matrix(b)
    assert np.allclose(ra @ rb, comcore.conventions.rotation_matrix(a + b))
    assert np.isclose(np.linalg.det(ra), 1.0)


def test_rotate_vectors_agrees_with_rotation_matrix():
    rng = np.random.default_rng(0)
    v = rng.normal(size=(5, 2))
    t = rng.uniform(-3, 3, size=5)
    expected = np.array([comcore.conventions.rotation_matrix(ti) @ vi for ti, vi in zip(t, v)])
    assert np.allclose(comcore.conventions.rotate_vectors(v, t), expected)


def test_ccw_cross_sign_matches_rotation_direction():
    # Turning +x by a small CCW angle: the moment of the turned vector is positive.
    v = comcore.conventions.rotate_vectors([[1.0, 0.0]], 0.1)[0]
    assert comcore.conventions.ccw_cross([1.0, 0.0], v) > 0


def test_rotation_sense_has_a_dead_band_of_angle_eps_by_default():
    eps = comcore.conventions.ANGLE_EPS
    sense = comcore.conventions.rotation_sense
    assert sense([1e-13, -0.5, 2.0]).tolist() == [0, -1, 1]
    assert sense([eps, -eps, 2 * eps, -2 * eps]).tolist() == [0, 0, 1, -1]  # the band is closed


def test_rotation_sense_takes_its_dead_band_as_tol():
    sense = comcore.conventions.rotation_sense
    assert sense([1e-13, -1e-300, 0.0, -0.0], tol=0.0).tolist() == [1, -1, 0, 0]  # the plain sign
    assert sense([0.1, -0.1, 0.3, -0.3], tol=0.2).tolist() == [0, 0, 1, -1]
    assert sense([5.0, -5.0], tol=np.inf).tolist() == [0, 0]  # a rotation not observed


def test_rotation_sense_keeps_the_shape_of_its_input():
    sense = comcore.conventions.rotation_sense
    theta = np.array([[0.2, -0.1, 0.0], [1e-13, -3.0, 0.5]])
    out = sense(theta)
    assert out.shape == (2, 3) and out.dtype.kind == "i"
    assert out.tolist() == [[1, -1, 0], [0, -1, 1]]
    assert sense(0.5).shape == () and int(sense(-0.5)) == -1
    assert sense(np.zeros(0)).shape == (0,)


@pytest.mark.parametrize("theta", [0.3, -0.3, 0.0, -0.0, 1e-13, -1e-13, 5e-324, -np.pi])
def test_motion_sense_is_rotation_sense_without_a_dead_band(theta):
    motion = comcore.Motion(theta, 1.0, 2.0)
    assert motion.sense == int(comcore.conventions.rotation_sense(theta, tol=0.0))
    assert type(motion.sense) is int


def test_the_identity_motion_moves_nothing():
    identity = comcore.Motion.identity()
    assert identity == comcore.Motion(0.0, 0.0, 0.0) and identity is comcore.Motion.identity()
    assert identity.sense == 0
    points = np.array([[3.0, 4.0], [-1.5, 2.0]])
    moved = comcore.apply_motion(points, identity.theta, (identity.tx, identity.ty), (1.0, 1.0))
    assert moved.tolist() == points.tolist()
    assert comcore.PushRecord(comcore.Action(0, 0, 1, 0), identity, "miss").pose_before == identity


def test_rotate_components_is_rotate_vectors_bit_for_bit():
    rng = np.random.default_rng(4)
    v, theta = rng.normal(size=(50, 2)) * 30, rng.uniform(-7, 7, 50)
    c, s = np.cos(theta), np.sin(theta)
    x, y = comcore.conventions.rotate_components(v[:, 0], v[:, 1], c, s)
    assert np.array_equal(np.column_stack([x, y]), comcore.conventions.rotate_vectors(v, theta))
    # the inverse turn is the turn by -theta, and with an origin it is added first
    xi, yi = comcore.conventions.rotate_components(v[:, 0], v[:, 1], c, s, inverse=True)
    assert np.array_equal(np.column_stack([xi, yi]), comcore.conventions.rotate_vectors(v, -theta))
    ox, oy = rng.normal(size=(2, 50)) * 100
    xo, yo = comcore.conventions.rotate_components(v[:, 0], v[:, 1], c, s, origin=(ox, oy))
    assert np.array_equal(xo, ox + c * v[:, 0] + s * v[:, 1])
    assert np.array_equal(yo, oy - s * v[:, 0] + c * v[:, 1])


def test_rotate_components_turns_a_y_up_frame_counter_clockwise_with_inverse():
    # In table metres (y up) a quarter turn takes +x to +y: the inverse of the pixel turn.
    c, s = np.cos(np.pi / 2), np.sin(np.pi / 2)
    x, y = comcore.conventions.rotate_components(1.0, 0.0, c, s, inverse=True, origin=(2.0, 3.0))
    assert (round(x, 12), round(y, 12)) == (2.0, 4.0)
    m = comcore.conventions.rotation_matrix(0.3)
    row = np.array([[1.5, -0.5]])
    xr, yr = comcore.conventions.rotate_components(1.5, -0.5, np.cos(0.3), np.sin(0.3), inverse=True)
    assert np.allclose(row @ m, [[xr, yr]], rtol=0, atol=1e-15)  # rows @ R(theta): the same turn


def test_quarter_turn_is_exact_and_agrees_with_rotate_vectors():
    v = np.array([[1.0, 0.0], [0.3, -2.0]])
    assert comcore.conventions.quarter_turn_ccw(v).tolist() == [[0.0, -1.0], [-2.0, -0.3]]
    assert np.allclose(comcore.conventions.quarter_turn_ccw(v), comcore.conventions.rotate_vectors(v, np.pi / 2))


def test_apply_motion_keeps_the_shape_of_one_point():
    out = comcore.apply_motion((1.0, 0.0), np.pi, (2.0, 3.0), (0.0, 0.0))
    assert out.shape == (2,) and np.allclose(out, [1.0, 3.0])
    assert comcore.apply_motion(np.zeros((0, 2)), 0.1, (0, 0), (0, 0)).shape == (0, 2)


@pytest.mark.parametrize(
    ("args", "error", "match"),
    [
        (([[1.0, 2.0]], np.nan, (0, 0), (0, 0)), ValueError, "theta must be a finite number"),
        (([[1.0, 2.0]], "0.1", (0, 0), (0, 0)), TypeError, "theta must be a number, got str"),
        (([[1.0, 2.0, 3.0]], 0.1, (0, 0), (0, 0)), ValueError, r"points must have shape \(n, 2\)"),
        (([[np.nan, 2.0]], 0.1, (0, 0), (0, 0)), ValueError, r"points must be finite.*\[0\]"),
        (([[1.0, 2.0]], 0.1, (0, np.inf), (0, 0)), ValueError, "translation must be finite"),
        (([[1.0, 2.0]], 0.1, (0, 0, 0), (0, 0)), ValueError, r"translation must be a single point of shape \(2,\), got shape \(3,\)"),
        (([[1.0, 2.0]], 0.1, (0, 0), [(0, 0), (1, 1)]), ValueError, "center must be a single"),
    ],
)
def test_apply_motion_rejects_bad_input(args, error, match):
    # NaN theta used to give NaN points and a (1, 3) points array a numpy broadcast error.
    with pytest.raises(error, match=match):
        comcore.apply_motion(*args)


@pytest.mark.parametrize(
    ("call", "error", "match"),
    [
        # [1, 2, 3] used to come back as a 2-vector built from its first two numbers.
        (lambda: comcore.conventions.rotate_vectors([1, 2, 3], 0.1), ValueError, r"vectors must have shape"),
        (lambda: comcore.conventions.rotate_vectors([[1, 0]], np.nan), ValueError, "theta must be finite"),
        (lambda: comcore.conventions.rotate_vectors([[1, 0]] * 3, [0.1, 0.2]), ValueError, "theta must broad"),
        (lambda: comcore.conventions.rotate_vectors("ab", 0.1), TypeError, "vectors must be array_like"),
        # used to return -0.0 from the first two numbers of a 3-vector
        (lambda: comcore.conventions.ccw_cross([1, 2, 3], [1, 2]), ValueError, r"a must have shape"),
        (lambda: comcore.conventions.ccw_cross([1, 2], [[1, 2, 3]]), ValueError, r"b must have shape"),
        (lambda: comcore.conventions.ccw_cross([[1, 2]] * 3, [[1, 2]] * 2), ValueError, "must broadcast"),
        (lambda: comcore.conventions.ccw_cross("ab", [1, 2]), TypeError, "a must be array_like"),
        (lambda: comcore.conventions.ccw_cross([np.inf, 0], [1, 2]), ValueError, "a must be finite"),
        # used to return -9223372036854775808 (NaN cast to int)
        (lambda: comcore.conventions.rotation_sense([np.nan]), ValueError, "theta must be finite"),
        (lambda: comcore.conventions.rotation_sense(["x"]), TypeError, "theta must be array_like"),
        (lambda: comcore.conventions.rotation_sense([0.1], tol=-1), ValueError, "tol must be a number >= 0"),
        (lambda: comcore.conventions.rotation_sense([0.1], tol="0"), TypeError, "tol must be a number"),
        (lambda: comcore.conventions.rotation_sense([0.1], tol=np.nan), ValueError, "tol must be a number >= 0"),
    ],
)
def test_convention_helpers_reject_bad_input(call, error, match):
    with pytest.raises(error, match=match):
        call()


def test_convention_helpers_still_broadcast():
    assert comcore.conventions.ccw_cross([[1.0, 0.0], [0.0, 1.0]], [0.0, 1.0]).tolist() == [-1.0, -0.0]
    assert comcore.conventions.rotate_vectors(np.zeros((2, 3, 2)), np.zeros(3)).shape == (2, 3, 2)
    assert comcore.conventions.rotation_sense(0.5).shape == ()


@pytest.mark.parametrize("theta", [np.nan, np.inf, -np.inf])
def test_rotation_matrix_refuses_an_angle_that_is_not_finite(theta):
    # It used to return a matrix of NaN that spread through every point it turned.
    with pytest.raises(ValueError, match="theta must be a finite angle in radians, got"):
        comcore.conventions.rotation_matrix(theta)


def test_rotation_matrix_takes_one_angle():
    with pytest.raises(ValueError, match=r"one angle in radians, got shape \(2,\)"):
        comcore.conventions.rotation_matrix([0.1, 0.2])
    with pytest.raises(TypeError, match="theta must be an angle in radians, got str"):
        comcore.conventions.rotation_matrix("0.1")
    assert np.allclose(comcore.conventions.rotation_matrix(np.float32(0.0)), np.eye(2))


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_quarter_turn_ccw_refuses_vectors_that_are_not_finite(bad):
    with pytest.raises(ValueError, match=r"finite pixel vectors \(x, y\); vector 2 is"):
        comcore.conventions.quarter_turn_ccw([[1.0, 0.0], [0.0, 1.0], [bad, 3.0]])
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 2\), got \(3,\)"):
        comcore.conventions.quarter_turn_ccw([1.0, 2.0, 3.0])


@pytest.mark.parametrize("radius", [0.001, 0.004, 0.01])
def test_an_action_is_the_path_of_the_pushers_leading_point(radius):
    # docs/explanation/conventions.md: the disc's centre runs one radius behind the action. A push along
    # the normal of a flat edge whose action ends 1 cm past the edge carries the object
    # 1 cm, whatever the radius, in the simulator and in the default motion model alike
    # (were the action the centre's path, it would carry it 1 cm minus the radius).
    simulators = require_simulators()
    square = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
    sim = simulators.PushSimulator.from_polygon(square, com=(0.0, 0.0), pusher_radius=radius)
    x, y = sim.to_pixels([(-0.03, 0.0)])[0]  # the middle of the left edge
    for past in (0.0, 0.01):
        action = comcore.Action(x - 8.0, y, x + past / sim.resolution, y)
        moved = sim.push(action).motion.tx * sim.resolution
        model = comcore.LimitSurfaceModel(pusher_radius=radius)
        predicted = model.predict_hypotheses(sim.mask, [action], [sim.mask.centroid], 0.5)
        assert moved == pytest.approx(past, abs=1e-6)
        assert predicted[0, 0, 1] * sim.resolution == pytest.approx(past, abs=1e-6)

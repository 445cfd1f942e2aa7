"""The session's pose from masks: a symmetric shape followed past its symmetry angle."""

import math

import pytest

import comcore
from comcore._session_pose import measure_pose

simulators = pytest.importorskip("simulators")


def test_a_rectangle_turned_past_half_a_turn_keeps_its_rotation():
    # A 2:1 rectangle has a 2-fold symmetry: from the masks alone a turn of 1.9 rad
    # looks like one of 1.9 - pi. Followed from 1.6 rad, the reading stays near 1.9.
    sim = simulators.PushSimulator.from_polygon(
        [(0, 0), (0.06, 0), (0.06, 0.03), (0, 0.03)], margin=0.05
    )
    first = sim.mask
    x, y, _ = sim.initial_pose
    mask = sim.mask_at((x, y, 1.9))
    reading = measure_pose(first, mask, comcore.Motion(1.6, 0.0, 0.0))
    assert abs(reading.pose.theta - 1.9) < math.radians(1.0)
    from_rest = measure_pose(first, mask, comcore.Motion(0.0, 0.0, 0.0))
    assert abs(from_rest.pose.theta - (1.9 - math.pi)) < math.radians(1.0)


def test_branches_of_a_hexagon_are_its_rotations_within_a_quarter_turn_of_the_pose():
    from comcore._session_pose import PoseReading, symmetric_branches

    reading = PoseReading(comcore.Motion(-0.5, 3.0, 1.0), False, 0.2, 6)
    branches = symmetric_branches(reading, comcore.Motion(0.2, 0.0, 0.0))
    thetas = [b.pose.theta for b in branches]
    assert thetas[0] == pytest.approx(-0.5 + 2 * math.pi / 6)  # nearest the previous pose first
    assert sorted(thetas) == pytest.approx([-0.5, -0.5 + math.pi / 3, -0.5 + 2 * math.pi / 3])
    assert all((b.pose.tx, b.pose.ty) == (3.0, 1.0) for b in branches)
    plain = reading._replace(symmetry=1)
    assert symmetric_branches(plain, comcore.Motion(0.2, 0.0, 0.0)) == [plain]

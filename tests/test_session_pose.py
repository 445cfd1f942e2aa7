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

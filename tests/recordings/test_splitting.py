"""split_pushes: one long log of object and pusher poses cut into pushes."""

import numpy as np
import pytest

from comcore.recordings import recording_from_poses, split_pushes

SQUARE = [(-0.03, -0.03), (0.03, -0.03), (0.03, 0.03), (-0.03, 0.03)]
RADIUS = 0.004


def pusher_log(gap, t):
    """The pusher below the square's bottom face, ``gap`` (m) from it, at x = 1 cm."""
    return np.column_stack([t, np.full_like(t, 0.01), -0.03 - RADIUS - gap, 0 * t])


def test_each_contact_between_two_separations_is_one_push():
    t = np.linspace(0.0, 6.0, 601)
    gap = 0.02 * np.abs(np.cos(np.pi * t / 2))  # touching at t = 1, 3, 5
    plate = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    pieces = split_pushes(SQUARE, plate, pusher_log(gap, t), RADIUS)
    assert len(pieces) == 3
    for k, (obj, pusher) in enumerate(pieces):
        assert pusher[0, 0] < 2 * k + 1 < pusher[-1, 0]  # each holds its touch
        assert obj[0, 0] <= pusher[0, 0] and obj[-1, 0] >= pusher[-1, 0]  # the object covers it
    # consecutive pieces share the sample where the pusher is away again
    assert pieces[0][1][-1, 0] == pieces[1][1][0, 0]
    # the last ends where the pusher is away after its touch (the rest of the log is no push)
    end = pieces[-1][1][-1, 0]
    assert 5 < end < 6 and 0.02 * abs(np.cos(np.pi * end / 2)) > 0.005


def test_a_gap_between_the_thresholds_neither_starts_nor_ends_a_push():
    t = np.linspace(0.0, 3.0, 301)
    # touch, back off to 4 mm (below the 5 mm separation), touch again, leave, touch
    gap = np.interp(t, [0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0], [0.02, 0, 0.004, 0, 0.02, 0.0, 0.0])
    plate = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    pieces = split_pushes(SQUARE, plate, pusher_log(gap, t), RADIUS)
    assert len(pieces) == 2
    assert len(split_pushes(SQUARE, plate, pusher_log(gap, t), RADIUS, separation=0.003)) == 3


def test_pieces_go_into_recording_from_poses_and_inputs_are_kept():
    t = np.linspace(0.0, 4.0, 401)
    gap = 0.02 * np.abs(np.cos(np.pi * t / 2)) - 0.015 * (np.abs(np.cos(np.pi * t / 2)) < 0.5)
    plate = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    pusher = pusher_log(gap, t)
    before = pusher.copy()
    pieces = split_pushes(SQUARE, plate, pusher, RADIUS)
    rec = recording_from_poses(SQUARE, pieces, RADIUS, travel=0.005)
    assert len(pieces) == 2 and len(rec.pushes) + len(rec.skipped) == 2
    assert np.array_equal(pusher, before)
    pieces[0][1][0, 1] = 9.0  # pieces are copies
    assert np.array_equal(pusher, before)


def test_no_contact_and_bad_arguments():
    t = np.linspace(0.0, 1.0, 11)
    plate = np.column_stack([t, 0 * t, 0 * t, 0 * t])
    assert split_pushes(SQUARE, plate, pusher_log(0.05 + 0 * t, t), RADIUS) == []
    later = pusher_log(0 * t, t + 5.0)  # outside the object's times
    assert split_pushes(SQUARE, plate, later, RADIUS) == []
    with pytest.raises(ValueError, match="separation .* must be at least contact_tolerance"):
        split_pushes(SQUARE, plate, later, RADIUS, separation=0.001)
    with pytest.raises(ValueError, match="pusher_radius"):
        split_pushes(SQUARE, plate, later, -1.0)
    with pytest.raises(ValueError, match="object_poses"):
        split_pushes(SQUARE, plate[:, :3], later, RADIUS)


@pytest.mark.parametrize("empty", [[], np.zeros((0, 4))])
def test_an_empty_pose_stream_is_refused_by_name(empty):
    t = np.linspace(0.0, 1.0, 101)
    pusher = np.column_stack([t, np.full_like(t, 0.01), -0.034 + 0.04 * t, 0 * t])
    with pytest.raises(ValueError, match="pushes\\[0\\] object poses .* got an empty stream"):
        recording_from_poses(SQUARE, [(empty, pusher)], 0.004)
    with pytest.raises(ValueError, match="pusher_poses .* got an empty stream"):
        split_pushes(SQUARE, pusher, empty, 0.004)
    with pytest.raises(ValueError, match="object_poses .* got an empty stream"):
        split_pushes(SQUARE, empty, pusher, 0.004)

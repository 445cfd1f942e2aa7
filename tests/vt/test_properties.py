"""Three laws of the Voting Theorem, written against the public API only (as the how-to shows).

docs/how-to/property-tests.md holds the same three tests; these run with more examples.
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from comcore import Action, Mask, vt
from comcore.geometry import contacts
from comcore.testing import strategies as cst

#: Rotations with a sense: no rotation (sense 0) leaves only CoMs exactly on a force line.
turns = cst.motions().filter(lambda m: abs(m.theta) > 0.01)


def region(mask, push, theta, mu):
    return vt.region(mask, push, theta, mu=mu, band=0.5, theta_tol=1e-9, pusher_radius=0.0)


@settings(max_examples=60, deadline=None)
@given(cst.masks_with_pushes(holes=None), cst.friction_ranges(), st.floats(0, 1), st.data())
def test_the_com_is_in_its_own_senses_region(mask_and_push, mu_range, where, data):
    mask, push = mask_and_push
    lo, hi = mu_range
    mu = lo + where * (hi - lo)
    com = np.floor(data.draw(cst.coms(mask)) + 0.5)  # the region is decided at pixel centres
    con = contacts(mask, push)
    sense = vt.predicted_sense(com, con.point[0], con.normal[0], push.direction, mu)
    assert region(mask, push, 0.1 * sense, mu_range)[int(com[1]), int(com[0])]


@settings(max_examples=60, deadline=None)
@given(cst.masks_with_pushes(holes=None), cst.friction_ranges(), turns, st.floats(0.05, 0.45))
def test_the_mirrored_push_gives_the_mirrored_region(mask_and_push, mu, motion, offset):
    mask, push = mask_and_push
    dx, dy = push.direction  # off the pixel centre it aims at (a tie on the push line)
    push = Action(push.sx - offset * dy, push.sy + offset * dx, push.ex - offset * dy, push.ey + offset * dx)
    if mask.contains([push.start])[0] or not contacts(mask, push).hit[0]:
        return
    w = mask.shape[1]
    mirrored = Mask(mask.data[:, ::-1], mask.resolution)
    mirrored_push = Action(w - 1 - push.sx, push.sy, w - 1 - push.ex, push.ey)
    assert np.array_equal(
        region(mirrored, mirrored_push, -motion.theta, mu), region(mask, push, motion.theta, mu)[:, ::-1]
    )


@settings(max_examples=60, deadline=None)
@given(cst.masks_with_pushes(holes=None), cst.friction_ranges(), st.floats(0, 1), st.floats(0, 1), turns)
def test_the_region_never_grows_as_the_friction_range_narrows(mask_and_push, wide, f1, f2, motion):
    mask, push = mask_and_push
    lo, hi = wide
    narrow = tuple(sorted((lo + f1 * (hi - lo), lo + f2 * (hi - lo))))
    assert np.all(region(mask, push, motion.theta, narrow) <= region(mask, push, motion.theta, wide))

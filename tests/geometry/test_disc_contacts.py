"""The estimators score a round pusher's contact, keep the pushes they can and report the rest."""

import pytest

import comcore

RADIUS = 0.00475  # metres: 1.9 px on the 2.5 mm/px square
GRAZING = (40.5, 0.0, 40.5, 20.0)  # straight down 1 px right of the square's right edge
INSIDE = (25.0, 25.0, 25.0, 35.0)  # starts on the object
HEAD_ON = [(0.0, 20.0, 30.0, 20.0), (25.0, 60.0, 25.0, 30.0), (45.0, 33.0, 20.0, 33.0)]


def test_the_grazing_push_is_the_one_the_line_misses_and_the_disc_hits(square_mask):
    assert not comcore.geometry.contacts(square_mask, [GRAZING]).hit[0]
    assert comcore.geometry.disc_contacts(square_mask, [GRAZING], RADIUS).hit[0]


def test_the_posterior_keeps_a_grazing_push_with_the_disc_and_reports_one_that_starts_inside(
    square_mask,
):
    actions = [*HEAD_ON, GRAZING, INSIDE]
    motions = [(0.05, 0.0, 0.0), (-0.05, 0.0, 0.0), (0.05, 0.0, 0.0), (0.05, 0.0, 0.0), (0.1, 0, 0)]
    est = comcore.estimate_posterior(
        square_mask, actions, motions, model=None, pusher_radius=RADIUS
    )
    assert list(est.used) == [0, 1, 2, 3]
    (skipped,) = est.skipped
    assert (skipped.index, skipped.reason) == (4, "starts_inside")
    assert "actions[4] starts inside the object" in skipped.detail
    # A point pusher (the leading line) cannot score the grazing push: it is reported too.
    point = comcore.estimate_posterior(square_mask, actions, motions, model=None, pusher_radius=0.0)
    assert list(point.used) == [0, 1, 2]
    assert [(s.index, s.reason) for s in point.skipped] == [
        (3, "misses"),
        (4, "starts_inside"),
    ]


def test_a_batch_that_mostly_misses_is_refused_with_the_likely_mistake(square_mask):
    actions = [HEAD_ON[0], INSIDE, (60.0, 60.0, 70.0, 70.0)]
    with pytest.raises(ValueError, match=r"2 of 3 do not .*x and y swapped\?"):
        comcore.estimate_posterior(
            square_mask, actions, [(0.05, 0, 0)] * 3, model=None, pusher_radius=RADIUS
        )


def test_the_session_never_offers_a_given_candidate_it_cannot_push_and_says_so(square_mask):
    candidates = [*HEAD_ON, INSIDE]
    session = comcore.ActiveSession(
        square_mask, candidates=candidates, model=None, pusher_radius=RADIUS, rng=0
    )
    assert [(s.index, s.reason) for s in session.skipped_candidates] == [(3, "starts_inside")]
    offered = []
    while not session.done:
        action = session.next_push()
        offered.append(tuple(action))
        session.observe(motion=(0.05, 0.0, 0.0))
    assert INSIDE not in offered and len(offered) <= len(HEAD_ON)


def test_alg2_scores_the_disc_contact_and_reports_what_it_left_out(square_mask):
    actions = [*HEAD_ON, GRAZING, INSIDE]
    motions = [(0.05, 0.0, 0.0), (-0.05, 0.0, 0.0), (0.05, 0.0, 0.0), (0.05, 0.0, 0.0), (0.1, 0, 0)]
    est = comcore.estimate_progressive(square_mask, actions, motions, pusher_radius=RADIUS)
    assert [(s.index, s.reason) for s in est.skipped] == [(4, "starts_inside")]
    assert 4 not in est.used


def test_the_voting_region_of_a_grazing_push_needs_the_pushers_radius(square_mask):
    region = comcore.vt.region(square_mask, GRAZING, 0.05, pusher_radius=RADIUS)
    assert 0 < region.sum() < square_mask.area_px
    with pytest.raises(ValueError, match="hit"):
        comcore.vt.region(square_mask, GRAZING, 0.05, pusher_radius=0.0)  # a point pusher misses

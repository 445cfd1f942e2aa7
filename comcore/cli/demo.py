"""``comcore demo``: a whole active session on a simulated object, and its estimate.

By default :class:`comcore.ActiveSession` pushes a simulated benchmark object through
``simulators.SimulatedRobot`` (never reset, seen through a camera) until it stops, then
prints the estimate, the size of its 90 % credible region and the true CoM. ``--compare``
prints instead the paper's two estimators (Alg. 1 and Alg. 2, given the simulator's motion
of every candidate push) beside the active estimator (:func:`comcore.estimate_active`) and
the centroid baseline.
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

import comcore

from ._options import non_negative_int, positive_int

HELP = (
    "run an active session on a simulated benchmark object and print its estimate, region and "
    "the true CoM; --compare: the paper's two estimators beside the active one (needs "
    "comcore[sim])"
)

#: What a status other than ``ok`` means here (printed under the table).
STATUS_NOTES = {
    "baseline": "the mask's area centroid: no push, no evidence",
    "unchecked": "Alg. 1 has no test of its evidence: its answer is never checked, never ok",
    "budget": "the active estimator spent its pushes (max_pushes) before its region was small",
    "exhausted": "no candidate push was left to make",
    "uninformative": "no push left was expected to teach anything",
    "inconsistent": "no CoM explains the observed motions well (Alg. 2: some pushes contradict "
    "the others; the estimate rests on the rest)",
    "no_actions": "no push turned the object enough to use",
    "flat_heatmap": "the pushes did not single out a region",
}


def _object_name(text: str) -> str:
    try:
        import simulators
    except ImportError:  # reported by run(), with the extra to install
        return text
    if text not in simulators.BENCHMARK_OBJECTS:
        raise argparse.ArgumentTypeError(
            f"unknown object {text!r}; expected one of Obj1..Obj{len(simulators.BENCHMARK_OBJECTS)}"
        )
    return text


def _cone(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number of radians, got {text!r}") from None
    if not (math.isfinite(value) and 0.0 <= value < math.pi / 2):
        raise argparse.ArgumentTypeError(f"expected radians in [0, pi/2), got {text}")
    return abs(value)  # -0.0 is 0.0


def add_arguments(parser) -> None:
    """Options of ``comcore demo``."""
    add = parser.add_argument
    add("--object", type=_object_name, default="Obj7", help="benchmark object (Obj1..Obj20)")
    add("--friction", choices=("low", "high"), default="low", help="friction class")
    add(
        "--pushes",
        type=positive_int,
        default=60,
        help="number of candidate pushes (with --compare)",
    )
    add(
        "--cone",
        type=_cone,
        default=0.3,
        help="push directions about the normal, radians (with --compare)",
    )
    add("--seed", type=non_negative_int, default=0, help="seed of the random draws")
    add(
        "--compare",
        action="store_true",
        help="compare the paper's Alg. 1 and Alg. 2 (given --pushes candidate pushes) with the "
        "active estimator and the centroid instead of running one session",
    )


def run(args) -> int:
    """Run the demo; returns the exit status (2 when the simulator's extra is missing)."""
    try:
        return _run(args)
    except ImportError as e:
        print(f"comcore demo needs the simulator: pip install comcore[sim] ({e})", file=sys.stderr)
        return 2


def _run(args) -> int:
    return _compare(args) if args.compare else _session(args)


def _session(args) -> int:
    """One :class:`comcore.ActiveSession` against a simulated robot; print what it found."""
    import simulators

    rng = np.random.default_rng(args.seed)
    sim = simulators.random_simulator(args.object, friction=args.friction, rng=rng)
    robot = simulators.SimulatedRobot(sim, rng=rng)
    first = robot.camera_mask()
    session = comcore.ActiveSession(first, pusher_radius=sim.pusher_radius, rng=rng)
    print(
        f"{args.object}: {first.area_m2 * 1e4:.1f} cm^2, mu_contact {sim.mu_contact:.2f}; "
        "an active session pushes it (a simulated robot, never reset, seen from above)"
    )
    while not session.done:
        try:
            push = robot.execute(session.next_push())
        except ValueError as e:  # the robot refused the push
            print(f"  push {robot.pushes + 1}: not made ({e})")
            session.observe(failed=True)
            continue
        session.observe(robot.camera_mask())
        print(f"  push {robot.pushes}: turned {math.degrees(push.motion.theta):+.1f} degrees")
    est = session.estimate()
    _print_session(est, robot.true_com_px, first.resolution)
    return 0


def _print_session(est: comcore.Estimate, truth, resolution: float) -> None:
    """The estimate, its region and the true CoM, in pixels of the first mask and in cm."""
    cm = 100 * resolution
    pushes = sum(p.outcome != "failed" for p in est.pushes)
    print(
        f"estimate: CoM ({est.com[0]:.1f}, {est.com[1]:.1f}) px, status {est.status} after "
        f"{pushes} pushes"
    )
    if est.posterior is not None:
        area = float(np.count_nonzero(est.region)) * cm * cm
        radius = est.posterior.credible_radius_px * cm * 10
        print(f"90 % region: {area:.2f} cm^2 (radius {radius:.1f} mm)")
    print(
        f"true CoM: ({truth[0]:.1f}, {truth[1]:.1f}) px; the estimate is "
        f"{est.error_px(truth) * cm:.2f} cm from it"
        + ("" if est.region_holds(truth) else ", outside the region")
    )


def _compare(args) -> int:
    import simulators
    from comcore.bench._report import ALG1_NOTE
    from predictors import OraclePredictor

    rng = np.random.default_rng(args.seed)
    sim = simulators.random_simulator(args.object, friction=args.friction, rng=rng)
    mask = sim.mask
    actions = comcore.sample_pushes(mask, args.pushes, cone=args.cone, rng=rng)
    motions = comcore.motion.predict_motions(OraclePredictor(sim), mask, actions)
    cm_per_px = 100 * mask.resolution
    print(
        f"{args.object}: {mask.area_m2 * 1e4:.1f} cm^2, mu_contact {sim.mu_contact:.2f}, "
        f"true CoM ({sim.com_px[0]:.1f}, {sim.com_px[1]:.1f}) px;\n  {args.pushes} candidate "
        "pushes, each one's simulated motion given to the paper's estimators"
    )
    active = comcore.estimate_active(  # the object put back before each of its pushes
        mask, lambda action: sim.push(action).motion, pusher_radius=sim.pusher_radius, rng=rng
    )
    baseline = comcore.Estimate(com=mask.centroid, com_m=mask.centroid_m, region=mask.data)
    heatmap = comcore.estimate_heatmap(mask, actions, motions)
    progressive = comcore.estimate_progressive(mask, actions, motions)
    made = sum(p.outcome != "failed" for p in active.pushes)
    rows = [  # (name, estimate, the pushes it rests on, the status shown)
        ("centroid (baseline)", baseline, 0, "baseline"),
        ("Alg. 1 heat map", heatmap, len(heatmap.used), heatmap.status),
        ("Alg. 2 progressive", progressive, len(progressive.used), progressive.status),
        ("active (its own pushes)", active, made, active.status),
    ]
    for name, est, pushes, status in rows:
        print(
            f"  {name:23s} CoM ({est.com[0]:6.1f}, {est.com[1]:6.1f}) px  "
            f"error {est.error_px(sim.com_px) * cm_per_px:5.2f} cm  "
            f"pushes {pushes:3d}  status {status}"
        )
    for status in dict.fromkeys(status for *_, status in rows):
        if status in STATUS_NOTES:
            print(f"  status {status}: {STATUS_NOTES[status]}")
    print(
        "  pushes: those an estimate rests on (Alg. 1 every candidate, Alg. 2 the ones it\n"
        "  chose); the active estimator's are the pushes it made itself"
    )
    if any(name.startswith("Alg. 1") for name, *_ in rows):
        print(f"  {ALG1_NOTE}")
    return 0

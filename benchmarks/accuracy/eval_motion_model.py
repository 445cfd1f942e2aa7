"""How well motion models predict a push, told the true CoM and friction.

For every benchmark object and friction class, ``--trials`` random trials
(``simulators.random_simulator``: random mass distribution, CoM and contact
friction), each pushed ``--pushes`` times with ``comcore.sample_pushes`` (3 cm
after contact; half along the inward normal, half within ``--cone`` rad of it).
The true motions come from the default exact quasi-static engine and from the
pymunk engine (the same object, mass and friction). The models are asked about
the true CoM and friction:

* ``limit-surface``: ``comcore.LimitSurfaceModel(pusher_radius=...)`` with its
  defaults, asked as the active estimator asks it (every pixel of the mask at
  once, the true CoM among them, so its lattice interpolation is included);
* ``limit-surface/key=value/...``: the same with those settings, e.g.
  ``limit-surface/pressure=linear`` or ``limit-surface/node_spacing=0/n_steps=16``
  (0: no interpolation, every hypothesis integrated);
* ``ellipsoid``: ``predictors.EllipsoidPredictor(pusher_radius=...)``.

The benchmark draws each trial's mass as uniform, a linear density gradient
or point masses, then tilts it exponentially to the drawn CoM; the
``tilted`` pressure is that very tilt of a uniform footprint, so the rows are
also given per mass style (``--by-style``; the style is re-drawn from the
trial's seed as ``random_simulator`` draws it) to show what matching the
benchmark's own pressure is worth.

Metrics per engine, model and friction class: how often the predicted sense
of rotation is the true one (pushes that turn the object by more than 2 deg),
median and 90th percentile of the rotation error (rad) by lever arm (the CoM's
distance to the push line), and of the error of the CoM's displacement
(metres: what the active likelihood compares); Obj19 (the 31 cm bar) apart.
``--fit-scales`` fits the Student-t (3 dof) error scales in the active
likelihood's form, ``a + b / (1 + (lever / 3.75 cm)^2)`` rad and
``c + d * |predicted displacement|`` m, by maximum likelihood;
``--scales a,b,c,d`` reports the coverage of given scales (tune on one seed,
report on another).

Usage::

    PYTHONPATH=. nice -n 10 python benchmarks/accuracy/eval_motion_model.py --seed 1 --fit-scales
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np
from scipy import optimize

import comcore
import simulators
from predictors import EllipsoidPredictor

BIG_ROTATION_RAD = np.radians(2.0)
LEVER_BINS_M = ((0.0, 0.01), (0.01, 0.03), (0.03, 1.0))
DEFAULT_MODELS = ("limit-surface", "ellipsoid")


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--objects", default="all", help="'all', a count (first N) or names: Obj1,Obj19")
    p.add_argument("--trials", type=int, default=2, help="trials per object and friction class")
    p.add_argument("--pushes", type=int, default=12, help="pushes per trial (half along normals)")
    p.add_argument("--cone", type=float, default=0.3)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--engines", default="quasistatic,pymunk")
    p.add_argument("--models", default=",".join(DEFAULT_MODELS),
                   help="ellipsoid, limit-surface, limit-surface/key=value/...")  # fmt: skip
    p.add_argument("--by-style", action="store_true", help="rows per mass style too")
    p.add_argument("--fit-scales", action="store_true", help="fit the error scales (ML)")
    p.add_argument("--scales", default=None, help="a,b,c,d: report these scales' coverage")
    p.add_argument("--json", default=None, help="write the residuals here")
    args = p.parse_args(argv)
    names = list(simulators.BENCHMARK_OBJECTS)
    if args.objects == "all":
        args.objects = names
    elif args.objects.isdigit():
        args.objects = names[: int(args.objects)]
    else:
        args.objects = [o.strip() for o in args.objects.split(",") if o.strip()]
    args.engines = [e.strip() for e in args.engines.split(",") if e.strip()]
    args.models = [m.strip() for m in args.models.split(",") if m.strip()]
    for name in args.models:
        try:
            make_model(name, 0.004)
        except (ValueError, TypeError) as e:
            p.error(f"bad model {name!r}: {e}")
    if args.trials < 1 or args.pushes < 2:
        p.error("--trials must be >= 1 and --pushes >= 2")
    if args.scales is not None:
        args.scales = [float(v) for v in args.scales.split(",")]
        if len(args.scales) != 4:
            p.error("--scales needs four numbers a,b,c,d")
    return args


def mass_style(sim, seed_seq):
    """The mass style ``random_simulator`` drew for this trial (its second draw)."""
    rng = np.random.default_rng(seed_seq)
    rng.uniform()  # the contact friction
    style = simulators.MASS_STYLES[int(rng.integers(len(simulators.MASS_STYLES)))]
    plain = simulators.MassDistribution.on_shape(sim.shape, com=sim.com_m)
    if (style == "point_masses") != (len(sim.mass.masses) > len(plain.masses)):
        raise RuntimeError("random_simulator's draws changed: --by-style cannot tell the style")
    return style


def trial_pushes(sim, n, cone, rng):
    """``n`` pushes (half along normals, half within ``cone``) the simulator accepts."""
    out = []
    for k, c in ((n // 2, 0.0), (n - n // 2, cone)):
        got = []
        for _ in range(20):
            for push in comcore.sample_pushes(sim.mask, k - len(got), cone=c, rng=rng):
                try:
                    sim.push(push)
                except ValueError:  # the disc would overlap the object at the start
                    continue
                got.append(push)
            if len(got) == k:
                break
        out.extend(got)
    return np.array(out)


def _value(text):
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def make_model(name, radius):
    """The model a ``--models`` entry names, for a pusher of ``radius`` metres."""
    if name == "ellipsoid":
        return EllipsoidPredictor(pusher_radius=radius)
    head, *options = name.split("/")
    if head != "limit-surface":
        raise ValueError("models are 'ellipsoid' or 'limit-surface[/key=value...]'")
    pairs = [o.split("=", 1) for o in options]
    if any(len(p) != 2 for p in pairs):
        raise ValueError("options are key=value")
    return comcore.LimitSurfaceModel(pusher_radius=radius, **{k: _value(v) for k, v in pairs})


def predict(name, sim, pushes):
    """Motions of the model ``name`` at the true CoM and friction, (n, 3)."""
    mask, com, mu = sim.mask, np.asarray(sim.com_px), sim.mu_contact
    model = make_model(name, sim.pusher_radius)
    if name == "ellipsoid" or model.node_spacing == 0:  # nothing interpolated: ask the CoM alone
        return model.predict_hypotheses(mask, pushes, com[None], mu)[0]
    hyps = np.vstack([com, mask.pixels])  # as the active estimator asks: one push at a time
    return np.stack([model.predict_hypotheses(mask, p[None], hyps, mu)[0, 0] for p in pushes])


def residuals(sim, pushes, pred, true):
    """Per push: lever (m), true and predicted theta, CoM displacement error and size (m)."""
    res = sim.mask.resolution
    com = np.asarray(sim.com_px)
    lever = np.abs(comcore.geometry.signed_line_distance(com[None], pushes)[0]) * res
    offset = com - np.asarray(sim.mask.centroid)

    def com_move(m):
        turned = comcore.conventions.rotate_vectors(np.tile(offset, (len(m), 1)), m[:, 0])
        return m[:, 1:] + turned - offset

    moved_pred = com_move(pred)
    err = np.hypot(*(com_move(true) - moved_pred).T) * res
    size = np.hypot(*moved_pred.T) * res
    return np.column_stack([lever, true[:, 0], pred[:, 0], err, size])


def run(args):
    rows = {}  # (engine, model, friction) -> list of residual arrays, with object names
    for oi, name in enumerate(args.objects):
        for fi, friction in enumerate(("low", "high")):
            for t in range(args.trials):
                seq = np.random.SeedSequence([args.seed, oi, fi, t])
                sim_seq, push_seq = seq.spawn(2)
                sim = simulators.random_simulator(
                    name, friction=friction, rng=np.random.default_rng(sim_seq)
                )
                style = mass_style(sim, sim_seq)
                push_rng = np.random.default_rng(push_seq)
                pushes = trial_pushes(sim, args.pushes, args.cone, push_rng)
                preds = {m: predict(m, sim, pushes) for m in args.models}
                for engine in args.engines:
                    settings = simulators.EngineSettings(engine=engine)
                    robot = sim.__class__(
                        sim.shape, sim.mass, mu_contact=sim.mu_contact, settings=settings
                    )
                    true = robot.push_motions(pushes)
                    for m, pred in preds.items():
                        r = residuals(sim, pushes, pred, true)
                        rows.setdefault((engine, m, friction), []).append((name, r))
                        if args.by_style:
                            key = (engine, m, f"{friction}, {style}")
                            rows.setdefault(key, []).append((name, r))
    return rows


def summary(r):
    """Sense agreement, rotation errors by lever bin and displacement errors of residual rows."""
    big = np.abs(r[:, 1]) > BIG_ROTATION_RAD
    sense = float(np.mean(np.sign(r[big, 1]) == np.sign(r[big, 2]))) if big.any() else np.nan
    dtheta = np.abs(r[:, 2] - r[:, 1])
    parts = [f"{sense:.3f}", f"{np.median(dtheta):.3f} / {np.percentile(dtheta, 90):.3f}"]
    for lo, hi in LEVER_BINS_M:
        sel = (r[:, 0] >= lo) & (r[:, 0] < hi)
        e = dtheta[sel]
        parts.append(f"{np.median(e):.3f} / {np.percentile(e, 90):.3f}" if sel.any() else "-")
    parts.append(f"{1e3 * np.median(r[:, 3]):.2f} / {1e3 * np.percentile(r[:, 3], 90):.2f}")
    return parts, len(r)


def table(rows, objects=None):
    bins = " | ".join(f"lever {100 * lo:g}-{100 * hi:g} cm" for lo, hi in LEVER_BINS_M[:-1])
    lines = [
        f"| engine | friction | model | sense | abs(dtheta) rad, median / p90 | {bins} "
        f"| lever > {100 * LEVER_BINS_M[-1][0]:g} cm | CoM displacement error (mm) | pushes |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    engines = list(dict.fromkeys(k[0] for k in rows))
    models = list(dict.fromkeys(k[1] for k in rows))
    classes = sorted({k[2] for k in rows}, key=lambda c: (c.split(",")[0] != "low", "," in c, c))
    for engine in engines:
        for friction in classes:
            for model in models:
                parts = rows.get((engine, model, friction), [])
                chosen = [r for n, r in parts if objects is None or n in objects]
                if chosen:
                    cells, n = summary(np.vstack(chosen))
                    row = f"| {engine} | {friction} | {model} | " + " | ".join(cells)
                    lines.append(row + f" | {n} |")
    return "\n".join(lines)


def _likelihood(params) -> comcore.Likelihood:
    """The active likelihood with error scales ``(a, b, c, d)`` (absolute values, above 0)."""
    a, b, c, d = np.abs(params)
    return comcore.Likelihood(theta_noise=(a + 1e-12, b), translation_error=(c + 1e-12, d))


def scales_nll(params, r):
    """Mean negative log-density of the residuals under the likelihood's model term."""
    theta_error = r[:, 2] - r[:, 1]
    density = _likelihood(params).model_error_log_density(theta_error, r[:, 0], r[:, 3], r[:, 4])
    return -float(density.mean())


def fit_scales(r):
    """Maximum-likelihood ``(a, b, c, d)`` of the Student-t error scales."""
    start = np.array([0.01, 0.1, 0.001, 0.05])
    best = optimize.minimize(scales_nll, start, args=(r,), method="Nelder-Mead",
                             options={"xatol": 1e-6, "fatol": 1e-6, "maxiter": 4000})  # fmt: skip
    return np.abs(best.x), best.fun


def coverage(scales, r):
    """Share of rotation and displacement residuals within 1, 2, 3 scales."""
    th_scale, tr_scale = _likelihood(scales).model_error_scales(r[:, 0], r[:, 4])
    th = np.abs(r[:, 2] - r[:, 1]) / th_scale
    tr = r[:, 3] / tr_scale
    return [float(np.mean(th <= k)) for k in (1, 2, 3)], [
        float(np.mean(tr <= k)) for k in (1, 2, 3)
    ]


def scale_report(rows, args):
    """Fitted and given scales per engine and model (friction classes pooled), and all engines."""
    pooled = {}
    for (engine, model, friction), parts in rows.items():
        if friction in ("low", "high"):
            pooled.setdefault((engine, model), []).extend(p for _, p in parts)
            pooled.setdefault(("all engines", model), []).extend(p for _, p in parts)
    for (engine, model), parts in sorted(pooled.items()):
        r = np.vstack(parts)
        label = f"{engine:11s} {model:40s}"
        if args.fit_scales:
            s, nll = fit_scales(r)
            print(f"{label} fitted a={s[0]:.4f} rad b={s[1]:.4f} rad "
                  f"c={1e3 * s[2]:.2f} mm d={s[3]:.3f}  nll/push {nll:.3f}")  # fmt: skip
        if args.scales is not None:
            th, tr = coverage(args.scales, r)
            nll = scales_nll(args.scales, r)
            print(f"{label} given scales: nll/push {nll:.3f}"
                  f"  rotation within 1/2/3 scales {th[0]:.2f}/{th[1]:.2f}/{th[2]:.2f}"
                  f"  displacement {tr[0]:.2f}/{tr[1]:.2f}/{tr[2]:.2f}")  # fmt: skip


def main(argv=None):
    args = parse_args(argv)
    t0 = time.perf_counter()
    rows = run(args)
    n_trials = len(args.objects) * 2 * args.trials
    print(f"{n_trials} trials x {args.pushes} pushes, seed {args.seed}, "
          f"{time.perf_counter() - t0:.0f} s\n")  # fmt: skip
    print(table(rows))
    if "Obj19" in args.objects:
        print("\nObj19 (the 31 cm bar) only:\n")
        print(table(rows, {"Obj19"}))
    if args.fit_scales or args.scales is not None:
        print()
        scale_report(rows, args)
    if args.json:
        out = {" / ".join(k): [[n, r.tolist()] for n, r in v] for k, v in rows.items()}
        with open(args.json, "w") as f:
            json.dump(out, f)


if __name__ == "__main__":
    main()

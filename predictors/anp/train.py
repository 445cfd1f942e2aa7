"""Train the ANP: ``python -m predictors.anp.train --episodes 4000 --epochs 30``.

Needs ``pip install comcore[anp,sim]`` (torch and tqdm; the simulator for
``--source sim``). Generates (or loads from ``--cache``) simulated episodes,
trains with the ANP evidence lower bound, keeps the model with the lowest
validation loss and writes it to ``--out`` (default ``./anp.pt`` in the
current directory; the shipped weights were written with an explicit
``--out predictors/anp/weights/anp.pt``) with a ``.json`` record next to it
(command, data size, time, peak memory, validation metrics, date). A
checkpoint (``CACHE/<OUT stem>.ckpt``) is written after every epoch;
``--resume`` continues from it. Each epoch's randomness is drawn from
``(seed, epoch)``, so a resumed run matches an uninterrupted one.
"""

from __future__ import annotations

import argparse
import datetime
import json
import math
import shlex
import sys
import time
from pathlib import Path

import numpy as np
import torch

from .data import featurise, load_or_generate, progress_bar
from .features import T_SCALE, THETA_SCALE, dihedral
from .model import AnpConfig, AnpModel
from .predictor import file_sha256, save_weights

__all__ = ["evaluate", "main", "peak_rss_mib", "train_epoch"]


def peak_rss_mib() -> dict:
    """Peak resident memory so far, in MiB, from ``resource.getrusage``.

    Returns
    -------
    dict
        ``self``: this process's peak; ``children``: the largest peak of the
        waited-for child processes (the ``--workers`` simulation processes),
        0 when there were none. Linux reports ``ru_maxrss`` in KiB, macOS in
        bytes; where the ``resource`` module is missing (Windows) both are ``None``.
    """
    try:
        import resource  # POSIX only
    except ImportError:  # Windows: not measured
        return {"self": None, "children": None}
    unit = 1 if sys.platform == "darwin" else 1024
    return {
        who: round(resource.getrusage(flag).ru_maxrss * unit / 2**20, 1)
        for who, flag in (("self", resource.RUSAGE_SELF), ("children", resource.RUSAGE_CHILDREN))
    }


def _tensors(d: dict, idx) -> tuple:
    return tuple(torch.from_numpy(np.ascontiguousarray(d[k][idx])) for k in ("image", "size"))


def train_epoch(model, optimizer, data: dict, *, epoch: int, seed: int, batch: int = 32,
                max_priors: int = 12, schedule=None, com_weight: bool = True) -> float:
    """One pass over ``data`` (from :func:`featurise`); returns the mean loss.

    Each batch draws a random symmetry of the square, a number of priors in
    ``[0, max_priors]`` and a random order of each episode's pushes. With
    ``com_weight`` the auxiliary CoM term of :meth:`AnpModel.loss` is used.
    """
    rng = np.random.default_rng([seed, epoch])
    torch.manual_seed(int(rng.integers(2**62)))
    model.train()
    n, n_pushes = data["features"].shape[:2]
    order = rng.permutation(n)
    losses = []
    for start in range(0, n - batch + 1 if n >= batch else 1, batch):
        idx = order[start : start + batch]
        perm = np.argsort(rng.random((len(idx), n_pushes)), axis=1)
        feats = np.take_along_axis(data["features"][idx], perm[..., None], axis=1)
        targs = np.take_along_axis(data["targets"][idx], perm[..., None], axis=1)
        image, feats, targs, com = dihedral(
            data["image"][idx], feats, targs, k=int(rng.integers(4)),
            flip=bool(rng.integers(2)), points=data["com"][idx],
        )
        k = int(rng.integers(0, min(max_priors, n_pushes - 1) + 1))
        loss, _ = model.loss(
            torch.from_numpy(image), torch.from_numpy(data["size"][idx]),
            torch.from_numpy(feats), torch.from_numpy(targs), n_priors=k,
            com=torch.from_numpy(com) if com_weight else None,
        )
        optimizer.zero_grad()
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), 1.0)
        optimizer.step()
        if schedule is not None:
            schedule.step()
        losses.append(loss.item())
    return float(np.mean(losses))


@torch.no_grad()
def evaluate(model, data: dict, n_priors: int = 12, batch: int = 64) -> dict:
    """Validation metrics with the first ``n_priors`` pushes as priors (at most all but one).

    Returns ``loss`` (the negated ELBO without the CoM term, fixed seed),
    ``nll`` (predictive negative log-likelihood at the latent mean, normalised
    units), ``theta_mae_deg``, ``t_mae_mm`` (error of the centroid's
    displacement), ``sense_acc`` (sense-of-rotation accuracy on queries
    turning more than 5 degrees, ``n_sense`` of them) and ``com_err_mm`` (the
    latent's CoM given the priors vs the true CoM).
    """
    model.eval()
    torch.manual_seed(0)
    n, n_pushes = data["features"].shape[:2]
    n_priors = min(n_priors, n_pushes - 1)
    losses, nlls, pred, true, com_err = [], [], [], [], []
    for s in range(0, n, batch):
        sl = slice(s, s + batch)
        image, size = _tensors(data, sl)
        feats = torch.from_numpy(data["features"][sl])
        targs = torch.from_numpy(data["targets"][sl])
        losses.append(float(model.loss(image, size, feats, targs, n_priors)[0]) * len(image))
        h_query, attended, q_z = model.context(
            image, size, feats[:, :n_priors], targs[:, :n_priors], feats[:, n_priors:]
        )
        dist = model.decode(h_query, attended, q_z.mean, feats[:, n_priors:])
        err = (model.com(q_z.mean) - torch.from_numpy(data["com"][sl])).norm(dim=-1)
        com_err.append(err.numpy() * data["length_m"][sl] * 1000)
        nlls.append(float(-dist.log_prob(targs[:, n_priors:]).mean()) * len(image))
        pred.append(dist.mean.numpy())
        true.append(targs[:, n_priors:].numpy())
    pred, true = np.concatenate(pred), np.concatenate(true)
    theta_p, theta_t = pred[..., 0] * THETA_SCALE, true[..., 0] * THETA_SCALE
    big = np.abs(theta_t) > np.deg2rad(5)
    t_err = np.hypot(*(pred[..., 1:] - true[..., 1:]).transpose(2, 0, 1)) * T_SCALE
    t_err_mm = t_err * data["length_m"][:, None] * 1000
    return {
        "loss": sum(losses) / n,
        "nll": sum(nlls) / n,
        "theta_mae_deg": float(np.rad2deg(np.abs(theta_p - theta_t).mean())),
        "t_mae_mm": float(t_err_mm.mean()),
        "com_err_mm": float(np.concatenate(com_err).mean()),
        "sense_acc": float((np.sign(theta_p[big]) == np.sign(theta_t[big])).mean())
        if big.any()
        else float("nan"),
        "n_sense": int(big.sum()),
    }


#: Arguments a resumed run must share with the run that wrote the checkpoint.
_RUN_KEYS = ("episodes", "val_episodes", "epochs", "seed", "source", "pushes", "batch", "lr",
             "width", "channels", "no_com_loss")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m predictors.anp.train", description=__doc__)
    p.add_argument("--episodes", type=int, default=4000, help="training episodes")
    p.add_argument("--val-episodes", type=int, default=256, help="validation episodes")
    p.add_argument("--epochs", type=int, default=30)
    p.add_argument("--out", type=Path, default=Path("anp.pt"),
                   help="weights file to write (default ./anp.pt; the shipped weights are "
                        "predictors/anp/weights/anp.pt)")
    p.add_argument("--cache", type=Path, default=Path(".cache/anp"), help="episode cache dir")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--resume", action="store_true", help="continue from CACHE/<OUT stem>.ckpt")
    p.add_argument("--source", choices=("sim", "toy"), default="sim")
    p.add_argument("--pushes", type=int, default=32, help="pushes per episode")
    p.add_argument("--batch", type=int, default=32)
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--width", type=int, default=AnpConfig.width)
    p.add_argument("--channels", type=int, nargs="+", default=list(AnpConfig.channels))
    p.add_argument("--workers", type=int, default=1, help="simulation processes")
    p.add_argument("--threads", type=int, default=1, help="torch CPU threads")
    p.add_argument("--no-com-loss", action="store_true", help="drop the auxiliary CoM term")
    return p


def _require_simulators() -> None:
    """Import the simulator, or say which extras training on it needs."""
    try:
        import simulators  # noqa: F401
    except ImportError as e:
        raise ImportError(
            "training on simulated episodes (--source sim) needs the simulator: "
            "pip install comcore[anp,sim]"
        ) from e


def _resume(ckpt: Path, run: str, model, optimizer, schedule) -> tuple:
    """Load ``ckpt`` into the model, optimizer and schedule: ``(history, first, best, seconds)``.

    Raises
    ------
    ValueError
        If the checkpoint was written by a run with other arguments than ``run``.
    """
    state = torch.load(ckpt, map_location="cpu", weights_only=True)
    if state["run"] != run:
        raise ValueError(
            f"--resume: checkpoint {str(ckpt)!r} was written by a run with other "
            f"arguments ({state['run']}); this run has {run}"
        )
    model.load_state_dict(state["model"])
    optimizer.load_state_dict(state["optimizer"])
    schedule.load_state_dict(state["schedule"])
    best = {k: v.clone() for k, v in state["best"].items()}
    return json.loads(state["history"]), state["epoch"] + 1, best, state["time"]


def _run_record(args, t_data: float, t_train: float) -> dict:
    """The run's arguments, sizes, times and memory for the training record."""
    return {
        "source": args.source, "seed": args.seed, "train_episodes": args.episodes,
        "val_episodes": args.val_episodes, "pushes_per_episode": args.pushes,
        "train_pushes": args.episodes * args.pushes, "data_seconds": round(t_data, 1),
        "train_seconds": round(t_train, 1), "peak_rss_mib": peak_rss_mib(),
        "epochs": args.epochs,
    }


def main(argv=None) -> dict:
    """Command-line entry point; returns the record written next to the weights."""
    args = _parser().parse_args(argv)
    if args.source == "sim":
        _require_simulators()
    torch.set_num_threads(args.threads)
    t0 = time.time()
    common = dict(n_pushes=args.pushes, source=args.source, cache=args.cache,
                  workers=args.workers, progress=True)
    train_ep = load_or_generate(args.episodes, seed=args.seed, **common)
    val_ep = load_or_generate(args.val_episodes, seed=args.seed + 10_000, **common)
    t_data = time.time() - t0
    config = AnpConfig(width=args.width, channels=tuple(args.channels))
    train, val = featurise(train_ep, config.image_size), featurise(val_ep, config.image_size)
    torch.manual_seed(args.seed)
    model = AnpModel(config)
    optimizer = torch.optim.AdamW(model.parameters(), lr=args.lr, weight_decay=1e-4)
    steps = args.epochs * max(1, args.episodes // args.batch)
    schedule = torch.optim.lr_scheduler.LambdaLR(
        optimizer, lambda s: min(1.0, (s + 1) / 200) * 0.5 * (1 + math.cos(math.pi * s / steps))
    )
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.cache.mkdir(parents=True, exist_ok=True)
    ckpt = args.cache / f"{args.out.stem}.ckpt"
    history, first, best, t_train = [], 0, None, 0.0
    run = json.dumps({k: v for k, v in vars(args).items() if k in _RUN_KEYS}, sort_keys=True)
    if args.resume and ckpt.exists():
        history, first, best, t_train = _resume(ckpt, run, model, optimizer, schedule)
    bar = progress_bar(iterable=range(first, args.epochs), initial=first, total=args.epochs,
                       desc="training")
    for epoch in bar:
        t1 = time.time()
        loss = train_epoch(model, optimizer, train, epoch=epoch, seed=args.seed,
                           batch=args.batch, schedule=schedule,
                           com_weight=not args.no_com_loss)
        metrics = evaluate(model, val)
        t_train += time.time() - t1
        history.append({"epoch": epoch, "train_loss": loss, **metrics})
        if best is None or metrics["loss"] <= min(h["loss"] for h in history):
            best = {k: v.detach().clone() for k, v in model.state_dict().items()}
        bar.set_postfix(loss=f"{loss:.3f}", val=f"{metrics['loss']:.3f}",
                        sense=f"{metrics['sense_acc']:.3f}")
        torch.save({"model": model.state_dict(), "optimizer": optimizer.state_dict(),
                    "schedule": schedule.state_dict(), "epoch": epoch, "time": t_train,
                    "history": json.dumps(history), "best": best, "run": run}, ckpt)
    model.load_state_dict(best)
    record = {
        "command": "python -m predictors.anp.train "
        + shlex.join(sys.argv[1:] if argv is None else argv),
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        **_run_record(args, t_data, t_train),
        "config": config.to_dict(), "validation": evaluate(model, val), "history": history,
        "torch": torch.__version__,
    }
    save_weights(model, args.out, meta={k: record[k] for k in ("command", "date", "source")})
    record["sha256"] = file_sha256(args.out)  # load_weights checks the file against it
    args.out.with_suffix(".json").write_text(json.dumps(record, indent=2) + "\n")
    return record


if __name__ == "__main__":  # pragma: no cover
    main()

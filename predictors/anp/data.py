"""Training episodes for the ANP: simulated pushes on random objects, cached to disk.

An episode is one object (a random polygon from :mod:`predictors.anp.shapes`,
a random mass distribution and contact friction from
``simulators.random_simulator``) pushed ``n_pushes`` times from its initial
pose with 3 cm pushes from :func:`comcore.sample_pushes`. Half the episodes
use the low friction class, half the high one. Episode ``i`` of a seed is a
function of ``(seed, i)`` alone, so a larger data set extends a smaller one
and the cache (``.npz`` chunks of :data:`CHUNK` episodes) is reused.

``source="toy"`` swaps the simulator for a cheap analytic stand-in (Voting
Theorem sense, lever-arm magnitude): for tests and development only.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from comcore import Mask, sample_pushes, vt
from comcore.conventions import ccw_cross, rotate_vectors
from comcore.geometry import contacts

from .features import object_frame, push_features, targets_from_motions
from .shapes import random_polygon, rasterise

__all__ = [
    "CHUNK",
    "Episodes",
    "featurise",
    "load_or_generate",
    "make_episode",
    "progress_bar",
    "toy_motions",
]

#: Episodes per cache file.
CHUNK = 64
#: Margin (pixels) kept around the object when an episode's mask is stored.
_STORE_MARGIN = 4
FRICTION = {"low": (0.1, 0.3), "high": (0.5, 0.9)}


@dataclass(frozen=True)
class Episodes:
    """A batch of episodes, as stored in the cache.

    Attributes
    ----------
    masks : list of numpy.ndarray of bool
        One cropped mask image per episode.
    resolution : numpy.ndarray, shape (E,)
    actions : numpy.ndarray, shape (E, P, 4)
        Pixels in the cropped mask's frame.
    motions : numpy.ndarray, shape (E, P, 3)
    com : numpy.ndarray, shape (E, 2)
        True CoM, pixels in the cropped mask's frame.
    mu : numpy.ndarray, shape (E,)
        Contact friction.
    """

    masks: list
    resolution: np.ndarray
    actions: np.ndarray
    motions: np.ndarray
    com: np.ndarray
    mu: np.ndarray

    def __len__(self) -> int:
        return len(self.masks)

    @staticmethod
    def concatenate(parts) -> Episodes:
        """Join several :class:`Episodes` in order."""
        parts = list(parts)
        return Episodes(
            masks=[m for p in parts for m in p.masks],
            **{
                k: np.concatenate([getattr(p, k) for p in parts])
                for k in ("resolution", "actions", "motions", "com", "mu")
            },
        )

    def save(self, path) -> None:
        """Write to an ``.npz`` (masks bit-packed, no pickles)."""
        shapes = np.array([m.shape for m in self.masks], dtype=np.int64).reshape(-1, 2)
        bits = [np.packbits(m.ravel()) for m in self.masks]
        offsets = np.cumsum([0] + [len(b) for b in bits])
        np.savez_compressed(
            path, shapes=shapes, offsets=offsets, bits=np.concatenate(bits), com=self.com,
            resolution=self.resolution, actions=self.actions, motions=self.motions, mu=self.mu,
        )

    @staticmethod
    def load(path) -> Episodes:
        """Read what :meth:`save` wrote."""
        with np.load(path, allow_pickle=False) as z:
            masks = [
                np.unpackbits(z["bits"][a:b], count=int(h * w)).reshape(h, w).astype(bool)
                for (h, w), a, b in zip(z["shapes"], z["offsets"][:-1], z["offsets"][1:])
            ]
            return Episodes(
                masks=masks, resolution=z["resolution"], actions=z["actions"],
                motions=z["motions"], com=z["com"], mu=z["mu"],
            )


def toy_motions(mask: Mask, actions, com, mu: float) -> np.ndarray:
    """Analytic stand-in for the simulator (tests, development): motions (n, 3).

    Sense from the Voting Theorem at the true CoM and ``mu``; the object turns
    about the CoM by ``travel * arm / (rho^2 + arm^2)`` (``arm``: the push
    line's distance to the CoM, ``rho``: the radius of gyration) and the CoM
    advances by the rest of the travel. Not physics: a learnable target.
    """
    con = contacts(mask, actions)
    acts = np.asarray(actions, float)
    d = acts[:, 2:] - acts[:, :2]
    length = np.hypot(d[:, 0], d[:, 1])
    direction = d / length[:, None]
    com = np.asarray(com, float)
    rho2 = float(((mask.pixels - com) ** 2).sum(axis=1).mean())
    arm = np.abs(ccw_cross(con.point - com, direction))
    travel = np.where(con.hit, length - con.travel, 0.0)
    sense = np.array(
        [
            int(vt.predicted_sense(com, p, nrm, u, mu)) if h else 0
            for p, nrm, u, h in zip(con.point, con.normal, direction, con.hit)
        ]
    )
    theta = sense * travel * arm / (rho2 + arm**2)
    shift = travel * rho2 / (rho2 + arm**2)
    centre = np.asarray(mask.centroid)
    t = shift[:, None] * direction + rotate_vectors(centre - com, theta) - (centre - com)
    return np.column_stack([theta, t])


def _crop(mask: Mask, actions, com):
    rows, cols = np.nonzero(mask.data)
    r0 = max(rows.min() - _STORE_MARGIN, 0)
    c0 = max(cols.min() - _STORE_MARGIN, 0)
    data = mask.data[r0 : rows.max() + _STORE_MARGIN + 1, c0 : cols.max() + _STORE_MARGIN + 1]
    shift = np.array([c0, r0], float)
    return data.copy(), actions - np.tile(shift, 2), np.asarray(com, float) - shift


def make_episode(seed, index: int, n_pushes: int, source: str = "sim"):
    """Simulate episode ``index`` of ``seed``: ``(mask, resolution, actions, motions, com, mu)``.

    Friction class alternates with ``index`` (even: low, odd: high); the
    push cone half-angle is uniform in [0, 0.6] rad. An object (with its mass
    distribution) that the simulator refuses to build is replaced by a new draw.
    """
    rng = np.random.default_rng(np.random.SeedSequence(int(seed), spawn_key=(int(index),)))
    friction = "low" if index % 2 == 0 else "high"
    vertices = random_polygon(rng)
    cone = rng.uniform(0.0, 0.6)
    if source == "toy":
        resolution = 0.0025
        mask = Mask(rasterise(vertices, resolution), resolution)
        pixels = mask.pixels
        weights = np.exp(rng.normal(0, 1.0) * (pixels - pixels.mean(0)) @ rng.normal(size=2) / 20)
        com = (weights[:, None] * pixels).sum(0) / weights.sum()
        mu = rng.uniform(*FRICTION[friction])
        actions = sample_pushes(mask, n_pushes, cone=cone, rng=rng)
        motions = toy_motions(mask, actions, com, mu)
    elif source == "sim":
        try:
            import simulators
        except ImportError as e:  # pragma: no cover
            raise ImportError("simulated training data need pip install comcore[anp,sim]") from e
        first = vertices

        def footprint(attempt):  # a refused draw takes another object
            return simulators.ObjectShape.from_vertices(
                first if attempt == 0 else random_polygon(rng)
            )

        sim = simulators.accepted_random_simulator(footprint, friction, rng=rng, attempts=20)
        mask, com, mu, resolution = sim.mask, sim.com_px, sim.mu_contact, sim.mask.resolution
        # each push simulated alone (the training data were made so); refused ones redrawn
        found = simulators.sample_accepted_pushes(
            sim, n_pushes, cone=cone, rng=rng, batched=False, draws=50
        )
        actions, motions = found.pushes, found.motions
    else:
        raise ValueError(f"source must be 'sim' or 'toy', got {source!r}")
    data, actions, com = _crop(mask, actions, com)
    return data, resolution, actions, np.asarray(motions, float), com, float(mu)


def _chunk(seed, start: int, stop: int, n_pushes: int, source: str) -> Episodes:
    eps = [make_episode(seed, i, n_pushes, source) for i in range(start, stop)]
    return Episodes(
        masks=[e[0] for e in eps],
        resolution=np.array([e[1] for e in eps]),
        actions=np.stack([e[2] for e in eps]),
        motions=np.stack([e[3] for e in eps]),
        com=np.stack([e[4] for e in eps]),
        mu=np.array([e[5] for e in eps]),
    )


def progress_bar(**kwargs):
    """A ``tqdm`` progress bar (``kwargs`` go to ``tqdm.tqdm``).

    Raises
    ------
    ImportError
        If tqdm is missing, naming the extra that brings it.
    """
    try:
        from tqdm import tqdm
    except ImportError as e:
        raise ImportError(
            "training the ANP shows progress with tqdm: pip install comcore[anp,sim]"
        ) from e
    return tqdm(**kwargs)


def load_or_generate(
    n_episodes: int, *, seed: int = 0, n_pushes: int = 32, source: str = "sim", cache=None,
    workers: int = 1, progress: bool = False,
) -> Episodes:
    """Episodes ``0 .. n_episodes - 1`` of ``seed``, from the cache where possible.

    Parameters
    ----------
    n_episodes : int
    seed : int, optional
    n_pushes : int, optional
        Pushes per episode (priors plus queries).
    source : {"sim", "toy"}, optional
    cache : path-like, optional
        Directory of cached chunks; ``None`` keeps nothing on disk.
    workers : int, optional
        Processes simulating chunks in parallel.
    progress : bool, optional
        Show a tqdm progress bar.
    """
    starts = list(range(0, n_episodes, CHUNK))
    folder = None if cache is None else Path(cache) / f"{source}-seed{seed}-p{n_pushes}"
    if folder is not None:
        folder.mkdir(parents=True, exist_ok=True)

    def path(s):
        return None if folder is None else folder / f"chunk{s // CHUNK:05d}.npz"

    todo = [s for s in starts if path(s) is None or not path(s).exists()]
    parts: dict[int, Episodes] = {}
    bar = None
    if progress and todo:
        bar = progress_bar(total=len(todo) * CHUNK, desc=f"simulating ({source})", unit="episode")

    def done(s, ep):
        parts[s] = ep
        if path(s) is not None:
            tmp = path(s).with_suffix(".tmp.npz")
            ep.save(tmp)
            tmp.replace(path(s))
        if bar is not None:
            bar.update(CHUNK)

    if workers > 1 and len(todo) > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(workers) as pool:
            futures = {s: pool.submit(_chunk, seed, s, s + CHUNK, n_pushes, source) for s in todo}
            for s, f in futures.items():
                done(s, f.result())
    else:
        for s in todo:
            done(s, _chunk(seed, s, s + CHUNK, n_pushes, source))
    if bar is not None:
        bar.close()
    for s in starts:
        if s not in parts:
            parts[s] = Episodes.load(path(s))
    return _head(Episodes.concatenate(parts[s] for s in starts), n_episodes)


def _head(ep: Episodes, n: int) -> Episodes:
    return Episodes(
        masks=ep.masks[:n], resolution=ep.resolution[:n], actions=ep.actions[:n],
        motions=ep.motions[:n], com=ep.com[:n], mu=ep.mu[:n],
    )


def featurise(episodes: Episodes, image_size: int = 64) -> dict:
    """Network inputs for every episode, float32 arrays.

    Keys: ``image`` (E, S, S), ``size`` (E,), ``features`` (E, P, F),
    ``targets`` (E, P, 3), ``com`` (E, 2) (true CoM in the frame), ``length_m`` (E,).
    """
    images, sizes, feats, targets, coms, lengths = [], [], [], [], [], []
    for i, data in enumerate(episodes.masks):
        mask = Mask(data, float(episodes.resolution[i]))
        frame = object_frame(mask, image_size)
        images.append(frame.image)
        sizes.append(frame.size_feature)
        coms.append(frame.to_frame(episodes.com[i]))
        lengths.append(frame.length_px * mask.resolution)
        feats.append(push_features(mask, frame, episodes.actions[i]))
        targets.append(targets_from_motions(episodes.motions[i], frame.length_px))
    return {
        "image": np.stack(images).astype(np.float32),
        "size": np.asarray(sizes, dtype=np.float32),
        "features": np.stack(feats).astype(np.float32),
        "targets": np.stack(targets).astype(np.float32),
        "com": np.stack(coms).astype(np.float32),
        "length_m": np.asarray(lengths, dtype=np.float32),
    }

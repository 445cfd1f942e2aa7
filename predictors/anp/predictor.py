""":class:`AnpPredictor`: the trained ANP behind comcore's ``Predictor`` protocol."""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from pathlib import Path

import numpy as np
import torch

from comcore.checks import check_actions, check_mask, check_priors, check_rng
from comcore.motion import (
    MAX_PUSH_THETA,
    MAX_TRANSLATION_PER_PUSH_LENGTH,
    check_plausible_motions,
)

from .features import (
    T_SCALE,
    THETA_SCALE,
    motions_from_targets,
    object_frame,
    push_features,
    targets_from_motions,
)
from .model import MIN_SIGMA, AnpConfig, AnpModel

__all__ = ["DEFAULT_WEIGHTS", "AnpPredictor", "file_sha256", "load_weights", "save_weights"]

#: The weights shipped with the package.
DEFAULT_WEIGHTS = Path(__file__).resolve().parent / "weights" / "anp.pt"
#: Tag and version written into every weights file.
WEIGHTS_FORMAT = "comcore-anp"
WEIGHTS_VERSION = 1
#: :meth:`AnpPredictor.estimate_com` refuses a CoM farther than this many object lengths
#: (the frame's ``length_px``, the object's diameter and a margin) outside the object's
#: bounding box: the CoM lies inside the footprint's convex hull, and the latent has left
#: what the model was trained on. Priors that no push can cause are refused before.
MAX_COM_OUTSIDE_LENGTHS = 0.5


def save_weights(model: AnpModel, path, meta: dict | None = None) -> Path:
    """Write ``model`` (config, parameters and ``meta``) to ``path``.

    The file holds only tensors and plain python values, so it loads with
    ``torch.load(path, weights_only=True)``.
    """
    path = Path(path)
    state = {k: v.detach().cpu().clone() for k, v in model.state_dict().items()}
    payload = {
        "format": WEIGHTS_FORMAT,
        "version": WEIGHTS_VERSION,
        "config": model.config.to_dict(),
        "state_dict": state,
        "meta": dict(meta or {}),
    }
    torch.save(payload, path)
    return path


def file_sha256(path) -> str:
    """The SHA-256 of a file's bytes, as 64 hex digits."""
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _recorded_sha256(path: Path) -> str | None:
    """The ``"sha256"`` of the training record next to ``path`` (``.json``), if any."""
    record = path.with_suffix(".json")
    if not record.is_file():
        return None
    try:
        value = json.loads(record.read_text()).get("sha256")
    except (ValueError, AttributeError) as e:
        raise ValueError(f"training record {str(record)!r} is not a JSON object: {e}") from e
    if value is not None and not (isinstance(value, str) and len(value) == 64):
        raise ValueError(f"training record {str(record)!r} has a malformed sha256: {value!r}")
    return value


def _check_finite(model: AnpModel, where: str) -> None:
    for name, tensor in model.state_dict().items():
        if tensor.is_floating_point() and not bool(torch.isfinite(tensor).all()):
            raise ValueError(f"{where} holds non-finite values (NaN or inf) in {name!r}")


def load_weights(path, sha256: str | None = None) -> tuple[AnpModel, dict]:
    """Read a weights file written by :func:`save_weights`.

    The file's SHA-256 is checked first, against ``sha256`` if given, else
    against the ``"sha256"`` of the training record next to it (``anp.json``
    beside ``anp.pt``, written by ``python -m predictors.anp.train``). The
    shipped weights must match their record; other files without a record are
    not checked. Every parameter must be finite.

    Raises
    ------
    FileNotFoundError
        No such file.
    ValueError
        The file's SHA-256 differs from the expected one (a corrupt or replaced
        file), the shipped weights have no recorded SHA-256, the file is not a
        comcore ANP weights file, its config is impossible, its parameters do
        not fit the model its config describes, or one is NaN or infinite.
    """
    path = Path(os.fspath(path))
    if not path.is_file():
        raise FileNotFoundError(
            f"weights file {str(path)!r} does not exist (train one with "
            "`python -m predictors.anp.train --out PATH`)"
        )
    expected = _recorded_sha256(path) if sha256 is None else str(sha256).lower()
    if expected is None and path.resolve() == DEFAULT_WEIGHTS:
        raise ValueError(
            f"the shipped weights' record {str(path.with_suffix('.json'))!r} has no sha256 "
            "to check them against"
        )
    if expected is not None:
        actual = file_sha256(path)
        if actual != expected:
            raise ValueError(
                f"weights file {str(path)!r} has SHA-256 {actual}, but {expected} was "
                "recorded: the file is corrupt or was replaced (restore it, e.g. with git, "
                "or retrain with `python -m predictors.anp.train --out PATH`)"
            )
    try:
        payload = torch.load(path, map_location="cpu", weights_only=True)
    except Exception as e:  # torch raises UnpicklingError, RuntimeError, EOFError ...
        raise ValueError(
            f"weights file {str(path)!r} is not a comcore ANP weights file "
            f"(torch.load failed: {type(e).__name__}: {e})"
        ) from e
    if not isinstance(payload, dict) or payload.get("format") != WEIGHTS_FORMAT:
        raise ValueError(
            f"weights file {str(path)!r} is not a comcore ANP weights file "
            f"(expected a dict with format={WEIGHTS_FORMAT!r})"
        )
    if payload.get("version") != WEIGHTS_VERSION:
        raise ValueError(
            f"weights file {str(path)!r} has format version {payload.get('version')!r}; "
            f"this comcore reads version {WEIGHTS_VERSION}"
        )
    try:
        model = AnpModel(AnpConfig.from_dict(payload.get("config")))
    except (TypeError, ValueError) as e:
        raise ValueError(f"weights file {str(path)!r} has a bad config: {e}") from e
    state = payload.get("state_dict")
    if not isinstance(state, dict):
        raise ValueError(f"weights file {str(path)!r} has no state_dict")
    try:
        model.load_state_dict(state, strict=True)
    except RuntimeError as e:
        raise ValueError(
            f"weights file {str(path)!r} does not match the ANP model its config describes: {e}"
        ) from e
    _check_finite(model, f"weights file {str(path)!r}")
    model.eval()
    return model, dict(payload.get("meta") or {})


class AnpPredictor:
    """Few-shot motion predictor: an attentive neural process (paper Sec. III-A).

    Conditions on prior pushes observed on the same object and predicts the
    motion ``(theta, tx, ty)`` of query pushes, with a variance. Implements
    :class:`comcore.Predictor`.

    Parameters
    ----------
    weights : str or path-like, optional
        A weights file from ``python -m predictors.anp.train``; default the
        weights shipped in ``predictors/anp/weights/anp.pt``.
    model : AnpModel, optional
        Use this (e.g. freshly trained) model instead of loading ``weights``.
    threads : int or None, optional
        torch CPU threads while predicting (default 1; restored afterwards).
        The model is small: one thread is enough (its time and the command
        that measures it: docs/how-to/your-predictor.md, "Inference time"). ``None``
        leaves torch's setting alone.

    Notes
    -----
    Pushes that do not hit the object from outside it (misses, starts inside)
    are predicted not to move it: motion 0 with the smallest variance.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> from predictors import AnpPredictor
    >>> anp = AnpPredictor()
    >>> mask = comcore.Mask(np.pad(np.ones((24, 16), bool), 12))
    >>> pushes = comcore.sample_pushes(mask, 5, rng=0)
    >>> priors = [(comcore.Action(*a), comcore.Motion(0.1, 8.0, 0.0)) for a in pushes[:3]]
    >>> anp.predict(mask, pushes[3:], priors).shape
    (2, 3)
    >>> mean, var = anp.predict_distribution(mask, pushes[3:], priors)
    >>> bool((var > 0).all())
    True
    """

    def __init__(self, weights=None, *, model: AnpModel | None = None, threads: int | None = 1):
        if threads is not None and (
            isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or threads < 1
        ):
            raise ValueError(f"threads must be None or an int >= 1, got {threads!r}")
        self.threads = None if threads is None else int(threads)
        if model is not None:
            if not isinstance(model, AnpModel):
                raise TypeError(f"model must be an AnpModel, got {type(model).__name__}")
            _check_finite(model, "model")
            self.model, self.meta = model.eval(), {}
            self.source = "a model given in code"
        else:
            path = DEFAULT_WEIGHTS if weights is None else weights
            self.model, self.meta = load_weights(path)
            self.source = f"weights {str(os.fspath(path))!r}"

    @property
    def config(self) -> AnpConfig:
        """The model's hyper-parameters."""
        return self.model.config

    def predict(self, mask, actions, priors=()) -> np.ndarray:
        """Predicted motions ``(theta, tx, ty)`` (radians, pixels), shape (n, 3).

        The decoder's mean at the mean of the latent given the priors:
        deterministic.
        """
        return self.predict_distribution(mask, actions, priors)[0]

    def predict_distribution(self, mask, actions, priors=(), n_samples: int = 0, rng=None):
        """Predictive mean and variance of the motions.

        Parameters
        ----------
        mask : Mask
        actions : array_like, shape (n, 4)
        priors : sequence of (Action, Motion)
        n_samples : int, optional
            0 (default): the decoder at the latent's mean, variance from the
            decoder alone. Otherwise average over this many latent samples
            (law of total variance: decoder variance plus the spread of the
            means), drawn with ``rng``.
        rng : None, int or numpy.random.Generator, optional

        Returns
        -------
        mean, var : numpy.ndarray, shape (n, 3)
            ``(theta, tx, ty)`` in radians and pixels, and their variances
            (radians^2, pixels^2).

        Raises
        ------
        ValueError
            If a prior's motion is physically impossible (``|theta|`` over pi,
            a translation over ten times its push's length): the message names
            ``priors[i]``. If a predicted mean is: the weights are
            broken (a weights file that is not checked against a training
            record can be corrupt and still finite). The message names the
            weights.
        """
        mask = check_mask(mask)
        acts = check_actions(actions)
        prior_actions, prior_motions = _check_prior_motions(*check_priors(priors))
        if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)):
            raise TypeError(f"n_samples must be an int >= 0, got {type(n_samples).__name__}")
        if n_samples < 0:
            raise ValueError(f"n_samples must be an int >= 0, got {n_samples}")
        rng = check_rng(rng)
        n = acts.shape[0]
        if n == 0:
            return np.zeros((0, 3)), np.zeros((0, 3))
        frame = object_frame(mask, self.config.image_size)
        query = push_features(mask, frame, acts)
        prior = push_features(mask, frame, prior_actions)
        targets = targets_from_motions(prior_motions, frame.length_px)
        with self._network():
            args = (
                torch.from_numpy(frame.image)[None],
                torch.tensor([frame.size_feature], dtype=torch.float32),
                torch.from_numpy(prior)[None],
                torch.from_numpy(targets)[None],
                torch.from_numpy(query)[None],
            )
            h_query, attended, q_z = self.model.context(*args)
            if n_samples == 0:
                dist = self.model.decode(h_query, attended, q_z.mean, args[-1])
                mean_t = dist.mean[0].double().numpy()
                var_t = dist.variance[0].double().numpy()
            else:
                seed = int(rng.integers(2**63 - 1))
                gen = torch.Generator().manual_seed(seed)
                eps = torch.randn((n_samples, q_z.mean.shape[-1]), generator=gen)
                z = q_z.mean + q_z.stddev * eps
                dist = self.model.decode(h_query.expand(n_samples, -1, -1),
                                         attended.expand(n_samples, -1, -1), z,
                                         args[-1].expand(n_samples, -1, -1))
                means, variances = dist.mean.double().numpy(), dist.variance.double().numpy()
                mean_t = means.mean(axis=0)
                var_t = variances.mean(axis=0) + means.var(axis=0)
        scale = np.array([THETA_SCALE, *(2 * [frame.length_px * T_SCALE])])
        mean = motions_from_targets(mean_t, frame.length_px)
        var = var_t * scale**2
        touches = query[:, 10] > 0.5
        mean[~touches] = 0.0
        var[~touches] = (MIN_SIGMA * scale) ** 2
        check_plausible_motions(mean, acts, f"AnpPredictor ({self.source})")
        return mean, var

    def estimate_com(self, mask, priors=()) -> tuple[float, float]:
        """The CoM ``(x, y)`` (pixels) that the model's latent stands for, given the priors.

        A by-product of training (the latent is asked to encode the true CoM);
        not one of the paper's estimators. With no priors it is the model's
        guess from the shape alone.

        Raises
        ------
        ValueError
            If a prior's motion is physically impossible, as in
            :meth:`predict_distribution` (naming ``priors[i]``), or the CoM comes
            out more than ``MAX_COM_OUTSIDE_LENGTHS`` object lengths outside the
            object's bounding box (refused, not clamped: the latent left the
            training range and no point of it can be trusted).
        """
        mask = check_mask(mask)
        prior_actions, prior_motions = _check_prior_motions(*check_priors(priors))
        frame = object_frame(mask, self.config.image_size)
        prior = push_features(mask, frame, prior_actions)
        targets = targets_from_motions(prior_motions, frame.length_px)
        with self._network():
            _, _, q_z = self.model.context(
                torch.from_numpy(frame.image)[None],
                torch.tensor([frame.size_feature], dtype=torch.float32),
                torch.from_numpy(prior)[None],
                torch.from_numpy(targets)[None],
                torch.zeros((1, 0, prior.shape[1])),
            )
            u = self.model.com(q_z.mean)[0].double().numpy()
        x, y = np.asarray(frame.center) + frame.length_px * u
        rows, cols = np.nonzero(mask.data)
        outside = max(cols.min() - 0.5 - x, x - cols.max() - 0.5,
                      rows.min() - 0.5 - y, y - rows.max() - 0.5)
        if not outside <= MAX_COM_OUTSIDE_LENGTHS * frame.length_px:  # NaN too
            raise ValueError(
                f"AnpPredictor ({self.source}) put the CoM at ({x:.4g}, {y:.4g}) px, "
                f"{outside:.3g} px outside the object's bounding box (the CoM lies inside "
                f"its outline): these priors are outside what the model was trained on"
            )
        return (float(x), float(y))

    @contextlib.contextmanager
    def _network(self):
        """Run torch without gradients, on ``threads``; a failure inside names these weights.

        Broken weights that are still finite (an exponent bit flipped) can make
        the network's internals overflow; torch then refuses a distribution's
        parameters deep inside. That is said here, once, with the weights.
        """
        with torch.no_grad(), self._threads():
            try:
                yield
            except (ValueError, RuntimeError) as e:
                first = str(e).splitlines()[0] if str(e) else type(e).__name__
                raise ValueError(
                    f"AnpPredictor ({self.source}) failed inside the network ({first}): the "
                    "weights are broken (corrupt or not trained for this model); restore or "
                    "retrain them (`python -m predictors.anp.train --out PATH`)"
                ) from e

    @contextlib.contextmanager
    def _threads(self):
        before = torch.get_num_threads()
        if self.threads is not None and self.threads != before:
            torch.set_num_threads(self.threads)
        try:
            yield
        finally:
            if torch.get_num_threads() != before:
                torch.set_num_threads(before)

    def __repr__(self) -> str:
        return f"AnpPredictor(config={self.config})"


def _check_prior_motions(actions: np.ndarray, motions: np.ndarray):
    """``(actions, motions)`` of the priors if a push can cause each motion, else a ValueError.

    The bounds of :func:`comcore.motion.check_plausible_motions`: at most half a turn, the
    centroid carried at most ``MAX_TRANSLATION_PER_PUSH_LENGTH`` times the push's length.
    A motion past them (a translation in the wrong unit, a number typed wrong) drove the
    latent far from its training range: the CoM it stood for came out 1e11 px off the image.
    """
    length = np.hypot(actions[:, 2] - actions[:, 0], actions[:, 3] - actions[:, 1])
    shift = np.hypot(motions[:, 1], motions[:, 2])
    for i in range(len(actions)):
        if abs(motions[i, 0]) > MAX_PUSH_THETA:
            raise ValueError(
                f"priors[{i}] turns the object by {motions[i, 0]:g} rad, more than half a turn "
                "(pi): theta must be in radians"
            )
        if shift[i] > MAX_TRANSLATION_PER_PUSH_LENGTH * length[i]:
            raise ValueError(
                f"priors[{i}] moves the object {shift[i]:.4g} px, more than "
                f"{MAX_TRANSLATION_PER_PUSH_LENGTH:g} times its push's length "
                f"({length[i]:.4g} px): no push carries an object that far; tx and ty must be "
                "in pixels of the mask"
            )
    return actions, motions

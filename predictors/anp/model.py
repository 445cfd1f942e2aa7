"""The attentive neural process (torch): mask CNN, push encoder, attention, latent, decoder.

Shapes: ``B`` episodes (objects), ``K`` prior pushes and ``Q`` query pushes per
episode, ``F = N_PUSH_FEATURES`` features per push, ``D`` model width.

Pipeline (paper Fig. 1, with the departures listed in ``docs/explanation/motion-models.md``):

1. A residual CNN encodes the object image (its normalised frame, two
   coordinate channels appended) ONCE per episode into a feature map and a
   pooled vector.
2. Each push is encoded from its frame features (start, end, contact, normal,
   ...), bilinear samples of the feature map at its start, contact and end
   points, the pooled vector and the object's size: ``h`` (B, n, D).
3. A prior adds its observed motion: ``r = MLP([h, y])``.
4. Deterministic path: multi-head cross-attention, queries ``h_query``, keys
   ``h_prior``, values ``r_prior``, plus one learned "no prior" token so that
   zero priors are allowed. Cost O(Q K).
5. Latent path: ``s = mean(MLP(r))`` -> ``Normal(mu_z, sigma_z)``, with a
   learned ``s`` for zero priors. Cost O(K).
6. Decoder: ``MLP([h_query, attention, z, g]) -> Normal(mean, sigma)`` over
   the three normalised motion components, where ``g`` is the query's lever
   geometry about the CoM that ``z`` stands for (a linear head ``com(z)``,
   trained with an auxiliary loss against the simulator's true CoM).
"""

from __future__ import annotations

import numbers
from dataclasses import asdict, dataclass

import torch
import torch.nn.functional as F
from torch import nn
from torch.distributions import Independent, Normal

from .features import N_PUSH_FEATURES

__all__ = ["AnpConfig", "AnpModel"]

#: Smallest predicted standard deviation (normalised units).
MIN_SIGMA = 0.01
#: Length scale (object lengths) of the auxiliary CoM term of :meth:`AnpModel.loss`.
COM_SCALE = 0.1


@dataclass(frozen=True)
class AnpConfig:
    """Hyper-parameters of :class:`AnpModel` (saved with the weights)."""

    image_size: int = 64
    channels: tuple[int, ...] = (16, 32, 64, 64)
    width: int = 128
    heads: int = 4
    latent: int = 32

    def to_dict(self) -> dict:
        """Plain-python form for the weights file."""
        d = asdict(self)
        d["channels"] = list(self.channels)
        return d

    @classmethod
    def from_dict(cls, d) -> AnpConfig:
        """Inverse of :meth:`to_dict`; raises ValueError on unknown or bad keys."""
        if not isinstance(d, dict):
            raise ValueError(f"config must be a dict, got {type(d).__name__}")
        known = set(cls.__dataclass_fields__)
        unknown = sorted(set(d) - known)
        if unknown:
            raise ValueError(
                f"config has unknown keys {unknown}; expected a subset of {sorted(known)}"
            )
        d = dict(d)
        if "channels" in d:
            try:
                d["channels"] = tuple(d["channels"])
            except TypeError as e:
                raise ValueError(
                    f"config channels must be a list of ints, got {d['channels']!r}"
                ) from e
        return cls(**d)

    def __post_init__(self):
        def count(value, name):
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
                raise ValueError(f"config {name} must be an int >= 1, got {value!r}")
            return int(value)

        for name in ("image_size", "width", "heads", "latent"):
            object.__setattr__(self, name, count(getattr(self, name), name))
        if not isinstance(self.channels, tuple) or not self.channels:
            raise ValueError(
                f"config channels must be a non-empty tuple of ints, got {self.channels!r}"
            )
        object.__setattr__(self, "channels", tuple(count(c, "channels") for c in self.channels))
        for c in self.channels:
            if c % min(8, c):  # GroupNorm(min(8, c), c)
                raise ValueError(f"config channels must be multiples of 8 (or below 8), got {c}")
        if self.width % self.heads:
            raise ValueError(f"config width {self.width} must be divisible by heads {self.heads}")


class _ResBlock(nn.Module):
    def __init__(self, c_in: int, c_out: int, stride: int):
        super().__init__()
        self.conv1 = nn.Conv2d(c_in, c_out, 3, stride, 1, bias=False)
        self.norm1 = nn.GroupNorm(min(8, c_out), c_out)
        self.conv2 = nn.Conv2d(c_out, c_out, 3, 1, 1, bias=False)
        self.norm2 = nn.GroupNorm(min(8, c_out), c_out)
        self.skip = (
            nn.Identity()
            if stride == 1 and c_in == c_out
            else nn.Conv2d(c_in, c_out, 1, stride, bias=False)
        )

    def forward(self, x):
        y = F.relu(self.norm1(self.conv1(x)))
        y = self.norm2(self.conv2(y))
        return F.relu(y + self.skip(x))


class _MaskEncoder(nn.Module):
    """Residual CNN: (B, 1, S, S) image -> (B, C, S/8, S/8) map and (B, C) vector."""

    def __init__(self, channels):
        super().__init__()
        c0 = channels[0]
        self.stem = nn.Sequential(nn.Conv2d(3, c0, 3, 1, 1), nn.ReLU())
        blocks, c_in = [], c0
        for i, c in enumerate(channels):
            blocks.append(_ResBlock(c_in, c, stride=1 if i == 0 else 2))
            c_in = c
        self.blocks = nn.Sequential(*blocks)

    def forward(self, image):
        b, _, s, _ = image.shape
        u = (2 * torch.arange(s, dtype=image.dtype, device=image.device) + 1) / s - 1
        yy, xx = torch.meshgrid(u, u, indexing="ij")
        coords = torch.stack([xx, yy]).expand(b, 2, s, s)
        fmap = self.blocks(self.stem(torch.cat([image, coords], dim=1)))
        return fmap, fmap.mean(dim=(2, 3))


class _CrossAttention(nn.Module):
    """Multi-head scaled dot-product attention written out with matmuls.

    Written by hand (not ``nn.MultiheadAttention``) so that every operation is
    a plain matmul whose cost a FLOP counter sees: O(Q K D).
    """

    def __init__(self, width: int, heads: int):
        super().__init__()
        self.heads = heads
        self.q = nn.Linear(width, width)
        self.k = nn.Linear(width, width)
        self.v = nn.Linear(width, width)
        self.out = nn.Linear(width, width)

    def forward(self, query, key, value):
        b, nq, d = query.shape
        h, dh = self.heads, d // self.heads

        def split(x):
            return x.reshape(b, -1, h, dh).transpose(1, 2)  # (B, h, n, dh)

        q, k, v = split(self.q(query)), split(self.k(key)), split(self.v(value))
        weights = torch.softmax(q @ k.transpose(-1, -2) / dh**0.5, dim=-1)
        return self.out((weights @ v).transpose(1, 2).reshape(b, nq, d))


def _mlp(d_in: int, d_hidden: int, d_out: int) -> nn.Sequential:
    return nn.Sequential(
        nn.Linear(d_in, d_hidden), nn.ReLU(), nn.Linear(d_hidden, d_hidden), nn.ReLU(),
        nn.Linear(d_hidden, d_out),
    )


class AnpModel(nn.Module):
    """Attentive neural process over pushes on one object per episode.

    Parameters
    ----------
    config : AnpConfig, optional
    """

    def __init__(self, config: AnpConfig | None = None):
        super().__init__()
        cfg = config or AnpConfig()
        self.config = cfg
        c, d = cfg.channels[-1], cfg.width
        self.cnn = _MaskEncoder(cfg.channels)
        self.push = _mlp(N_PUSH_FEATURES + 3 * c + c + 1, d, d)
        self.prior = _mlp(d + 3, d, d)
        self.attention = _CrossAttention(d, cfg.heads)
        self.norm = nn.LayerNorm(d)
        self.null_key = nn.Parameter(torch.zeros(1, 1, d))
        self.null_value = nn.Parameter(torch.zeros(1, 1, d))
        self.latent_in = _mlp(d, d, d)
        self.null_summary = nn.Parameter(torch.zeros(1, d))
        self.latent_out = nn.Linear(d, 2 * cfg.latent)
        self.com_head = nn.Linear(cfg.latent, 2)
        self.decoder = _mlp(2 * d + cfg.latent + 4, d, 6)

    # -- encoders -----------------------------------------------------------------
    def encode_pushes(self, fmap, pooled, size, features):
        """Push embeddings ``h``, shape (B, n, D), from (B, n, F) frame features."""
        b, n, _ = features.shape
        if n == 0:  # no priors and no queries (grid_sample's output cannot be reshaped)
            return features.new_zeros((b, 0, self.config.width))
        points = torch.stack([features[..., 0:2], features[..., 6:8], features[..., 2:4]], 2)
        grid = points.reshape(b, n * 3, 1, 2)
        samples = F.grid_sample(fmap, grid, mode="bilinear", align_corners=False)
        samples = samples.reshape(b, -1, n, 3).permute(0, 2, 3, 1).reshape(b, n, -1)
        glob = torch.cat([pooled, size[:, None]], dim=1)[:, None, :].expand(b, n, -1)
        return self.push(torch.cat([features, samples, glob], dim=-1))

    def latent(self, r):
        """``Normal`` over z from prior encodings ``r`` (B, K, D); K may be 0."""
        if r.shape[1] == 0:
            s = self.null_summary.expand(r.shape[0], -1)
        else:
            s = self.latent_in(r).mean(dim=1)
        mu, raw = self.latent_out(F.relu(s)).chunk(2, dim=-1)
        return Independent(Normal(mu, 0.01 + 0.99 * torch.sigmoid(raw)), 1)

    def attend(self, h_query, h_prior, r_prior):
        """Cross-attention from queries (B, Q, D) to priors (B, K, D)."""
        b = h_query.shape[0]
        keys = torch.cat([self.null_key.expand(b, -1, -1), h_prior], dim=1)
        values = torch.cat([self.null_value.expand(b, -1, -1), r_prior], dim=1)
        return self.norm(h_query + self.attention(h_query, keys, values))

    def com(self, z):
        """The CoM that latent ``z`` (B, latent) stands for, frame coordinates (B, 2)."""
        return self.com_head(z)

    def decode(self, h_query, attended, z, query_features):
        """``Normal`` over normalised motions, batch shape (B, Q), event shape (3,).

        Besides the embeddings, the decoder sees the query's geometry relative
        to the CoM that ``z`` stands for: the moments about it of a unit force
        along the push and along the contact normal, the contact's offset
        from it along the push, and its distance.
        """
        r = query_features[..., 6:8] - self.com(z)[:, None, :]
        d, n = query_features[..., 4:6], query_features[..., 8:10]
        geometry = torch.stack(
            [
                r[..., 1] * d[..., 0] - r[..., 0] * d[..., 1],  # conventions.ccw_cross(r, d)
                r[..., 1] * n[..., 0] - r[..., 0] * n[..., 1],
                (r * d).sum(-1),
                r.norm(dim=-1),
            ],
            dim=-1,
        )
        z = z[:, None, :].expand(-1, h_query.shape[1], -1)
        inputs = torch.cat([h_query, attended, z, geometry], dim=-1)
        mean, raw = self.decoder(inputs).chunk(2, dim=-1)
        return Independent(Normal(mean, MIN_SIGMA + F.softplus(raw)), 1)

    # -- whole passes -------------------------------------------------------------
    def context(self, image, size, prior_features, prior_targets, query_features):
        """Encode an episode; returns ``(h_query, attended, q_z)``.

        Parameters
        ----------
        image : Tensor, shape (B, S, S)
        size : Tensor, shape (B,)
        prior_features : Tensor, shape (B, K, F)
        prior_targets : Tensor, shape (B, K, 3)
        query_features : Tensor, shape (B, Q, F)
        """
        fmap, pooled = self.cnn(image[:, None])
        k = prior_features.shape[1]
        h = self.encode_pushes(fmap, pooled, size, torch.cat([prior_features, query_features], 1))
        h_prior, h_query = h[:, :k], h[:, k:]
        r_prior = self.prior(torch.cat([h_prior, prior_targets], dim=-1))
        return h_query, self.attend(h_query, h_prior, r_prior), self.latent(r_prior)

    def forward(self, image, size, prior_features, prior_targets, query_features, z=None):
        """Predictive ``Normal`` for the queries given ``z`` (default: the latent mean)."""
        h_query, attended, q_z = self.context(
            image, size, prior_features, prior_targets, query_features
        )
        return self.decode(h_query, attended, q_z.mean if z is None else z, query_features)

    def loss(self, image, size, features, targets, n_priors: int, com=None):
        """ANP evidence lower bound (negated, per target) for one batch of episodes.

        The first ``n_priors`` pushes of each episode are the context, the rest
        the targets. The latent posterior is conditioned on all pushes (as in
        Kim et al. 2019), the prior on the context only; their KL comes from
        ``torch.distributions.kl_divergence``. When the true CoM ``com`` (B, 2)
        (frame coordinates) is given, an auxiliary term asks the latent means
        to stand for it: ``|com(z) - com|^2 / (2 COM_SCALE^2)``, averaged.

        Returns
        -------
        loss : Tensor
            Scalar: ``nll + kl + com_term``.
        parts : dict of float
            ``nll``, ``kl`` (per target push) and ``com`` (0 without ``com``).
        """
        fmap, pooled = self.cnn(image[:, None])
        h = self.encode_pushes(fmap, pooled, size, features)
        r = self.prior(torch.cat([h, targets], dim=-1))
        k = n_priors
        h_query = h[:, k:]
        attended = self.attend(h_query, h[:, :k], r[:, :k])
        prior_z = self.latent(r[:, :k])
        posterior_z = self.latent(r)
        z = posterior_z.rsample()
        nll = -self.decode(h_query, attended, z, features[:, k:]).log_prob(targets[:, k:]).mean()
        kl = torch.distributions.kl_divergence(posterior_z, prior_z).mean() / h_query.shape[1]
        com_term = torch.zeros(())
        if com is not None:
            for q in (prior_z, posterior_z):
                err = ((self.com(q.mean) - com) ** 2).sum(-1).mean()
                com_term = com_term + 0.5 * err / (2 * COM_SCALE**2)
        loss = nll + kl + com_term
        return loss, {"nll": nll.item(), "kl": kl.item(), "com": com_term.item()}

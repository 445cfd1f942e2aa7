"""What an active session has seen: the pushes, the states and the evidence.

:class:`SessionLog` keeps one record per reported push (its action and motion
in the camera and the object frame, its outcome) and one state per
observation (posterior mean, entropy, credible radius, log evidence), and
sums each hypothesis' excess surprise: how much more the pushes surprise it
than its own motions would (:func:`comcore._session_update.push_evidence`).
The best hypothesis' sum says whether any (CoM, friction, model) explains the
data (:attr:`SessionLog.consistent`).
"""

from __future__ import annotations

import math

import numpy as np

from ._posterior import GridPosterior
from ._session_update import consistency_threshold

__all__ = ["SessionLog"]


class SessionLog:
    """Records, states and evidence of a session or an offline posterior (internal)."""

    def __init__(self, post: GridPosterior, credible: float):
        self.credible = credible
        self.records: list[dict] = []
        self.history: list[dict] = []
        self.excess = np.zeros(post.log_w.shape)
        self.log_evidence = 0.0
        self.state(post)

    def state(self, post: GridPosterior) -> None:
        """Record the posterior's state (after an observation, or the prior)."""
        _, area = post.credible(self.credible)
        self.history.append(
            {
                "com": tuple(float(v) for v in post.mean()),
                "entropy_bits": post.entropy_bits(),
                "credible_radius_px": math.sqrt(area / math.pi),
                "expected_gain_bits": None,
                "log_evidence": self.log_evidence,
                "excess_nats": self.excess_nats,
            }
        )

    def add(self, record: dict, post: GridPosterior, loglik=None, excess=None) -> None:
        """Add a push's record; with evidence, multiply its likelihood into ``post``."""
        if loglik is not None:
            record["log_evidence"] = post.update(loglik.tempered, loglik.full)
            self.excess = self.excess + excess
            self.log_evidence += record["log_evidence"]
        self.records.append(record)
        self.state(post)

    @property
    def executed(self) -> list[dict]:
        """Records of the pushes that were executed (evidence or miss)."""
        return [r for r in self.records if r["outcome"] != "failed"]

    @property
    def n_evidence(self) -> int:
        """Number of pushes that carried evidence."""
        return sum(r["outcome"] == "evidence" for r in self.records)

    @property
    def excess_nats(self) -> float:
        """The best hypothesis' summed excess surprise (nats; 0 before any evidence)."""
        return float(self.excess.min()) if self.n_evidence else 0.0

    @property
    def consistent(self) -> bool:
        """False when even the best hypothesis is surprised beyond ``10 + 6 sqrt(n)`` nats."""
        n = self.n_evidence
        return n == 0 or self.excess_nats <= consistency_threshold(n)

    def rows(self, key: str, width: int) -> np.ndarray:
        """One field of the executed pushes as an array (k, width)."""
        return np.array([r[key] for r in self.executed], dtype=float).reshape(-1, width)

    def extras(self) -> dict:
        """The Estimate's extras about the pushes and the evidence."""
        return {
            "actions": self.rows("object_action", 4),
            "motions": self.rows("object_motion", 3),
            "outcomes": tuple(r["outcome"] for r in self.executed),
            # what a replay (estimate_posterior) needs to score the pushes as they were
            "rotation_observed": tuple(not r.get("ambiguous", False) for r in self.executed),
            "residual_px": tuple(float(r.get("residual_px", math.nan)) for r in self.executed),
            "failed": tuple(r["index"] for r in self.records if r["outcome"] == "failed"),
            "log_evidence": self.log_evidence,
            "excess_nats": self.excess_nats,
        }

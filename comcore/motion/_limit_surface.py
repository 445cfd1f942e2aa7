"""The exact-limit-surface motion model: :class:`LimitSurfaceModel`.

The physics is in :mod:`comcore.motion._physics`, the pressure family
in :mod:`comcore.motion._pressure`. A push's motion depends on the CoM hypothesis
only through the pressure consistent with it, smoothly, so the model
integrates the push for CoMs on a coarse grid of nodes and interpolates
bilinearly to the hypotheses asked about.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass
from functools import partial

import numpy as np
from scipy import ndimage

from .._mask import Mask
from .._neighbourhood import LocalArrays, margin_px
from .._validation import check_actions, check_mask, check_number, check_points
from ..conventions import check_plausible
from ..geometry._disc_contacts import outline_field
from ._lattice import (
    PushLattice,
    _table_step,
    expect_frictions,
    pressure_table,
    remembered,
    table_pressures,
    widened,
)
from ._physics import SMOOTHING_CELLS, push_motions
from ._pressure import PRESSURES, pressures, support

__all__ = ["FAMILY", "LimitSurfaceModel", "check_push_lengths"]

#: The pressure spreads :meth:`LimitSurfaceModel.family` weighs: the exponential
#: and the clipped linear tilt of a uniform footprint (see docs/explanation/motion-models.md).
FAMILY = ("tilted", "linear")

_NEAREST: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: How far (in node spacings) from a hypothesis the nodes it is interpolated from lie: a
#: cell's diagonal, at most sqrt(2) spacings; the pressure table starts that far round the object.
_LATTICE_REACH = 1.5


def _nearest(data: np.ndarray, window) -> tuple[np.ndarray, np.ndarray]:
    """(row, col) of the nearest object pixel, whole-image indices, on a window holding it."""
    rows, cols = ndimage.distance_transform_edt(
        ~window.crop(data), return_distances=False, return_indices=True
    )
    return rows + window.lo[0], cols + window.lo[1]


def _nearest_pixel(mask: Mask) -> LocalArrays:
    """For every pixel, the (row, col) of the nearest object pixel (cached per mask).

    On the object's neighbourhood (:mod:`comcore._neighbourhood`), grown when asked elsewhere:
    a window that holds every object pixel gives the whole image's answer.
    """
    out = _NEAREST.get(mask)
    if out is None:
        margin = margin_px(mask.resolution)
        out = _NEAREST[mask] = LocalArrays(
            mask._box.grown_by(margin), partial(_nearest, mask.data), 0, margin
        )
    return out


def _on_object(mask: Mask, points: np.ndarray) -> np.ndarray:
    """Points moved to their nearest object pixel where they are not on one."""
    h, w = mask.shape
    rows = np.clip(np.rint(points[:, 1]).astype(np.intp), 0, h - 1)
    cols = np.clip(np.rint(points[:, 0]).astype(np.intp), 0, w - 1)
    exact = (rows == np.rint(points[:, 1])) & (cols == np.rint(points[:, 0]))
    near_r, near_c = _nearest_pixel(mask).at(rows, cols)
    moved = np.column_stack([near_c, near_r]).astype(float)
    return np.where((mask.data[rows, cols] & exact)[:, None], points, moved)


def check_push_lengths(mask: Mask, actions: np.ndarray, name: str = "actions") -> np.ndarray:
    """``actions`` if each is at least a pixel long, else a ValueError with that push's numbers.

    A push shorter than a pixel moves nothing the camera can see: it comes of
    lengths set in metres over a resolution in the wrong unit (3 cm at 2.5
    "metres" per pixel is 0.012 px), and the lattice such a push is integrated
    on would be sized by the same mistake.

    Examples
    --------
    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((4, 4), bool), 3))
    >>> check_push_lengths(mask, np.array([[0.0, 4.5, 3.2, 4.5], [0.0, 4.5, 0.01, 4.5]]))
    Traceback (most recent call last):
    ...
    ValueError: actions[1] is 0.01 px long (2.5e-05 m at 0.0025 m per pixel): a push must be at least a pixel long; are its lengths in metres and the mask's resolution in metres per pixel?
    """  # noqa: E501
    lengths = np.hypot(actions[:, 2] - actions[:, 0], actions[:, 3] - actions[:, 1])
    short = np.flatnonzero(lengths < 1.0)
    if len(short):
        i = int(short[0])
        raise ValueError(
            f"{name}[{i}] is {lengths[i]:.3g} px long ({lengths[i] * mask.resolution:.3g} m at "
            f"{mask.resolution:g} m per pixel): a push must be at least a pixel long; are its "
            "lengths in metres and the mask's resolution in metres per pixel?"
        )
    return actions


@dataclass(frozen=True)
class LimitSurfaceModel:
    """Quasi-static pushing with the footprint's exact limit surface (a :class:`comcore.Predictor`).

    The floor's friction is integrated over the mask's pixels (gathered into
    about ``support_points`` blocks) under a pressure consistent with each
    CoM hypothesis: its centre of pressure is the CoM. How the pressure is
    spread is unknown; ``pressure`` picks one of three spreads, and
    :meth:`family` gives the pair the active estimator should weigh (as it
    weighs the friction). A round pusher of ``pusher_radius`` metres pushes
    with contact friction ``mu`` (sticking or sliding: Mason's motion cone),
    integrated over the push in ``n_steps`` steps: the object turns and the
    contact moves along the outline. See ``docs/explanation/motion-models.md``.

    Parameters
    ----------
    pusher_radius : float, optional
        Radius of the round pusher, metres (0: a point; at most 5 cm,
        ``comcore.conventions.PLAUSIBLE``). An action is the path of the disc's leading
        point, as in :mod:`simulators`.
    pressure : {"tilted", "linear", "peaked"}, optional
        ``"tilted"`` (default): the uniform footprint tilted exponentially (the
        spread closest to uniform in relative entropy); ``"linear"``: tilted
        linearly, clipped at zero; ``"peaked"``: falling off linearly from the
        CoM, then tilted linearly (mass near the CoM).
    n_steps : int, optional
        Integration steps after first contact (default 8).
    support_points : int, optional
        About how many blocks of pixels carry the pressure (default 32).
    node_spacing : float, optional
        Spacing (metres, default 1 cm) of the CoM nodes the push is
        integrated for, along the push and far from its line (2.5 mm at the
        line); the motions of other CoMs are interpolated bilinearly. 0
        integrates every hypothesis (slow, exact).
    batch_pressures : tuple of str, optional
        Pressure spreads integrated in the same batch as this one (and
        remembered for the models that use them): :meth:`family` sets it, so
        that weighing the family costs little more than one model.

    Examples
    --------
    A 5 x 7.5 cm plate pushed to the right along row 19.5: a CoM above the
    line (smaller row) turns it counter-clockwise, one on the line not at all:

    >>> import numpy as np, comcore
    >>> mask = comcore.Mask(np.pad(np.ones((20, 30), bool), 10))
    >>> model = comcore.LimitSurfaceModel(pusher_radius=0.004)
    >>> coms = [(24.5, 15.0), (24.5, 19.5)]
    >>> out = model.predict_hypotheses(mask, [(0, 19.5, 24, 19.5)], coms, 0.5)
    >>> out.shape, bool(out[0, 0, 0] > 0.05), abs(float(out[1, 0, 0])) < 1e-9
    ((2, 1, 3), True, True)
    >>> [m.pressure for m in comcore.LimitSurfaceModel.family(pusher_radius=0.004)]
    ['tilted', 'linear']
    """

    pusher_radius: float = 0.0
    pressure: str = "tilted"
    n_steps: int = 8
    support_points: int = 32
    node_spacing: float = 0.01
    batch_pressures: tuple[str, ...] = ()

    def __post_init__(self):
        radius = check_number(self.pusher_radius, "pusher_radius")
        if radius < 0:
            raise ValueError(f"pusher_radius must be >= 0 (metres), got {radius}")
        radius = check_plausible(radius, "pusher_radius", "pusher_radius")
        object.__setattr__(self, "pusher_radius", radius)
        if self.pressure not in PRESSURES:
            raise ValueError(f"pressure must be one of {PRESSURES}, got {self.pressure!r}")
        for name, low in (("n_steps", 1), ("support_points", 4)):
            value = check_number(getattr(self, name), name, integer=True)
            if value < low:
                raise ValueError(f"{name} must be an integer >= {low}, got {int(value)}")
            object.__setattr__(self, name, int(value))
        batch = self.batch_pressures
        if not isinstance(batch, (tuple, list)) or any(b not in PRESSURES for b in batch):
            raise ValueError(f"batch_pressures must be a tuple of {PRESSURES}, got {batch!r}")
        object.__setattr__(self, "batch_pressures", tuple(batch))
        spacing = check_number(self.node_spacing, "node_spacing")
        if spacing < 0:
            raise ValueError(f"node_spacing must be >= 0 metres (0: none), got {spacing}")
        check_plausible(spacing, "node_spacing", "push_length")
        object.__setattr__(self, "node_spacing", spacing)

    @classmethod
    def family(cls, pusher_radius: float = 0.0, **options) -> tuple[LimitSurfaceModel, ...]:
        """One model per pressure spread of :data:`FAMILY`, to weigh as several models.

        ``comcore.estimate_active(mask, push, model=LimitSurfaceModel.family(r))``
        marginalises the unknown spread with a uniform prior, as it does the
        friction. ``options`` are passed to every model.
        """
        options = {**options, "batch_pressures": FAMILY}
        return tuple(cls(pusher_radius, pressure, **options) for pressure in FAMILY)

    def _motions(
        self, mask: Mask, actions: np.ndarray, press: np.ndarray, mu, same_as=None, path=False
    ):
        """Integrated motions under pressures ``press`` (n, N), shape (n, n_actions, 3).

        ``path=True``: after every step, (n, n_actions, n_steps + 1, 3).
        """
        sup = support(mask, self.support_points)
        eps2 = (SMOOTHING_CELLS * sup.cell) ** 2 / mask.area_px  # relative to the push speed
        radius = self.pusher_radius / mask.resolution
        return push_motions(
            outline_field(mask),
            actions,
            press,
            sup.points,
            np.asarray(mask.centroid),
            mu=mu,
            radius=radius,
            n_steps=self.n_steps,
            eps2=eps2,
            same_as=same_as,
            path=path,
        )

    def _pressures(self, mask: Mask, coms: np.ndarray, spread: str | None = None) -> np.ndarray:
        """Pressures for CoMs (moved onto the object), (n, N)."""
        sup = support(mask, self.support_points)
        rel = _on_object(mask, coms) - np.asarray(mask.centroid)
        return pressures(sup, rel, self.pressure if spread is None else spread)

    def expect_frictions(self, mask, mus) -> None:
        """Say that the next pushes will be asked about each friction of ``mus`` in turn.

        Optional, for estimators (``comcore.estimate_active`` calls it): the
        first push on a mask is then integrated for every friction value in one
        batch, as later pushes are, instead of once per value. The motions are
        the same either way.
        """
        expect_frictions(check_mask(mask), np.atleast_1d(np.asarray(mus, dtype=float)))

    def predict_hypotheses(self, mask, actions, coms, mu) -> np.ndarray:
        """Motions of each action for each CoM hypothesis (:class:`comcore.Predictor`).

        Parameters
        ----------
        mask : comcore.Mask
        actions : array_like, shape (n_actions, 4)
        coms : array_like, shape (n_coms, 2)
            CoM hypotheses in pixels; one off the object is taken at the
            nearest object pixel (a pressure needs its centre on the footprint).
        mu : float
            Contact friction, ``>= 0`` (``inf``: the contact never slides).

        Returns
        -------
        numpy.ndarray, shape (n_coms, n_actions, 3)
            ``(theta, tx, ty)``: rotation (CCW on screen) and displacement
            (pixels) of the material point under the mask's area centroid;
            zeros for a push that misses.

        Raises
        ------
        ValueError
            If an action starts inside the object or is shorter than a pixel
            (:func:`check_push_lengths`), or ``mu`` is negative or NaN.
        TypeError
            If ``mu`` is not a number.
        """
        mask = check_mask(mask)
        acts = check_push_lengths(mask, check_actions(actions))
        pts = check_points(coms, "coms")
        mu = check_number(mu, "mu", allow_inf=True)
        if mu < 0:
            raise ValueError(f"mu must be >= 0 (inf allowed), got {mu}")
        if len(acts) == 0 or len(pts) == 0:
            return np.zeros((len(pts), len(acts), 3))
        if self.node_spacing == 0:
            return self._motions(mask, acts, self._pressures(mask, pts), mu)
        last = np.array([self.n_steps])  # the push's end: the one state interpolated
        return np.concatenate(
            [self._interpolated(mask, a, pts, mu, last)[:, None, 0] for a in acts], axis=1
        )

    def predict_path_hypotheses(self, mask, action, coms, mu, fractions) -> np.ndarray:
        """Motions part way along one push, for each CoM hypothesis, shape (n_coms, J, 3).

        The optional method of :class:`comcore.Predictor` that the
        frames of a push are scored with (:mod:`comcore.active._path`): the
        push integrated once, its state after each of its ``n_steps`` steps
        kept, and read at ``fractions`` (J,) of its travel after first contact
        (linearly between steps). A predictor without it is asked about the
        push cut short at each fraction instead.

        Parameters
        ----------
        mask : comcore.Mask
        action : array_like, shape (4,)
        coms : array_like, shape (n_coms, 2)
        mu : float
        fractions : array_like, shape (J,)
            In [0, 1].
        """
        mask = check_mask(mask)
        act = check_push_lengths(mask, check_actions(np.asarray(action, float)[None]))
        pts = check_points(coms, "coms")
        mu = check_number(mu, "mu", allow_inf=True)
        if mu < 0:
            raise ValueError(f"mu must be >= 0 (inf allowed), got {mu}")
        f = np.asarray(fractions, dtype=float).reshape(-1)
        if not np.isfinite(f).all() or (f < 0).any() or (f > 1).any():
            raise ValueError(f"fractions must lie in [0, 1], got {f.tolist()}")
        if len(act) == 0 or len(pts) == 0:
            return np.zeros((len(pts), len(f), 3))
        where = f * self.n_steps
        lo = np.minimum(np.floor(where).astype(np.intp), self.n_steps - 1)
        w = (where - lo)[None, :, None]
        if self.node_spacing == 0:
            states = self._motions(mask, act, self._pressures(mask, pts), mu, path=True)[:, 0]
            return states[:, lo] * (1 - w) + states[:, lo + 1] * w
        # only the steps the fractions fall between are interpolated from the lattice
        steps, index = np.unique(np.concatenate([lo, lo + 1]), return_inverse=True)
        states = self._interpolated(mask, act[0], pts, mu, steps)
        below, above = index[: len(lo)], index[len(lo) :]
        return states[:, below] * (1 - w) + states[:, above] * w

    def _interpolated(self, mask: Mask, action: np.ndarray, pts: np.ndarray, mu: float, steps):
        """States of one push after the steps ``steps``, interpolated from its lattice's nodes.

        Shape (n, len(steps), 3); step ``n_steps`` is the push's motion, 0 the rest
        before it. Each step is interpolated on its own (bilinear in the nodes), so
        asking for the few steps a caller reads costs that many, not ``n_steps + 1``.
        """
        spreads = tuple(p for p in PRESSURES if p == self.pressure or p in self.batch_pressures)
        settings = (self.pusher_radius, self.n_steps, self.support_points, self.node_spacing)
        key = (settings, spreads, action.tobytes())
        near = mask._box.grown_by(margin_px(mask.resolution))  # the object's neighbourhood
        lattice, known, mus = remembered(
            mask,
            key,
            lambda: PushLattice(mask, action, self.node_spacing, near),
            mu,
            spreads,
            shape=(self.n_steps + 1, 3),
        )
        found = lattice.cells(pts)
        if found is None:  # a hypothesis off the neighbourhood: the whole image's lattice
            lattice, known = widened(
                mask, key, lambda: PushLattice(mask, action, self.node_spacing)
            )
            found = lattice.cells(pts)
        corners, weights, keys = found
        if len(keys) >= len(pts):  # interpolation would not save anything
            press = self._pressures(mask, pts)
            return self._motions(mask, action[None], press, mu, path=True)[:, 0][:, steps]
        todo = keys[np.isnan(known[self.pressure, mu][keys, -1, 0])]
        if len(todo):
            self._integrate_nodes(
                mask, action, lattice, todo, known=known, mus=mus, spreads=spreads
            )
        motion = known[self.pressure, mu][:, steps]  # (nodes, len(steps), 3)
        return np.einsum("kn,knts->nts", weights, motion[corners])

    def _integrate_nodes(self, mask, action, lattice, todo, *, known, mus, spreads):
        """Integrate the push at nodes for every pressure spread and friction not yet known.

        One batch: per spread the friction values highest first, so that a row
        that sticks can move as its spread's highest-friction copy does.
        """
        n, points = len(todo), lattice.points[todo]
        jobs = [
            (spread, m)
            for spread in spreads
            for m in sorted(mus, reverse=True)
            if np.isnan(known[spread, m][todo, -1, 0]).all()
        ]
        press, same = {}, []
        for k, (spread, _) in enumerate(jobs):
            if spread not in press:
                table = pressure_table(
                    mask,
                    (spread, self.support_points),
                    lambda m, p, spread=spread: self._pressures(m, p, spread),
                    reach_px=_LATTICE_REACH * lattice.spacing,
                )
                press[spread] = (table_pressures(table, points, _table_step(mask)), k)
            same.append(press[spread][1] * n + np.arange(n))
        out = self._motions(
            mask,
            action[None],
            np.vstack([press[spread][0] for spread, _ in jobs]),
            np.repeat([m for _, m in jobs], n),
            same_as=np.concatenate(same),
            path=True,
        )[:, 0]
        for k, job in enumerate(jobs):
            known[job][todo] = out[k * n : (k + 1) * n]

"""The motion model's term of a push's path: the frames' poses given the end pose.

The model predicts, per hypothesis, the pose
after each frame's travel (the same push cut short there), and the residuals
``r_j`` (observed minus predicted rotation, and displacement of the hypothesis' CoM, as
:func:`comcore.active._motion_term.motion_terms` compares the end pose) are not
independent: a model that is wrong about a push is wrong about all of it. Per
component, with ``f_j`` the travel after contact as a fraction of the push's::

    r_j = f_j e + w W(f_j) + n_j,   e ~ s,  W a Brownian motion of scale s,  n_j ~ tracking

``e`` the push's shared model error (scale ``s``: the end pose's model scale), ``w``
(``Likelihood.path_wander``) the part of the model's error that is not shared along the
push, ``n_j`` the tracker's error. The end pose keeps its own term (unchanged: a session
without frames scores exactly as before); the frames add the log density of the path's
residuals *given the end's*, a multivariate Student-t (3 degrees of freedom, as the end
terms) whose covariance is that of the model above conditioned on ``r_K``. With ``w``
small the path says much (the model's error is a shape it must keep along the push);
with ``w`` large the frames add little beyond the end pose. The consistency check
(:func:`comcore.active._likelihood.consistency_threshold`) reads the end poses alone, as
before.

:mod:`comcore.active._path` reads the frames into the path this scores;
:mod:`comcore.active._likelihood` adds it to the model's term of the push.
"""

from __future__ import annotations

import numpy as np

from ._motion_term import STUDENT_DOF, com_shift

__all__ = ["path_log_likelihood"]


def path_log_likelihood(
    path, observed_end, predicted_end, predicted_path, offset, scales, *, wander: float
):
    """Log density of a push's path given its end pose, per hypothesis, shape (p, m, k).

    Parameters
    ----------
    path : PushPath
        The kept poses (object frame), ``J`` of them, each frame's travel after
        contact as a fraction of the push's, in (0, 1), and the frames' tracking
        standard deviations (radians, pixels) (:class:`comcore.active._path.PushPath`).
    observed_end : numpy.ndarray, shape (3,)
    predicted_end : numpy.ndarray, shape (p, m, k, 3)
        The model's end motion per hypothesis (as the end term scores it).
    predicted_path : numpy.ndarray, shape (p, m, k, J, 3)
        The model's motion after each kept frame's travel.
    offset : numpy.ndarray, shape (p, 1, 1, 2)
        Each hypothesis' CoM minus the first mask's centroid (pixels).
    scales : (float or numpy.ndarray, float or numpy.ndarray)
        The model's error scales at the end, rotation (radians) and translation
        (pixels), without tracking, each broadcast to (p, m, k): one per push as
        the session scores it (then the covariance is factored once for every
        hypothesis), or one per hypothesis.
    wander : float
        ``Likelihood.path_wander``.
    """
    theta_scale, translation_scale = scales
    tracking = path.tracking
    obs = np.vstack([np.asarray([p.motion for p in path.points], float), observed_end[None]])
    pred = np.concatenate([predicted_path, predicted_end[..., None, :]], axis=-2)  # (.., K, 3)
    f = np.append(np.asarray(path.fractions, float), 1.0)
    cov = np.outer(f, f) + wander**2 * np.minimum.outer(f, f)
    lam, vecs = np.linalg.eigh(cov)
    lam = np.maximum(lam, 1e-12)
    end_var = 1.0 + wander**2
    off = offset[..., None, :]  # (p, 1, 1, 1, 2)
    theta_res = obs[:, 0] - pred[..., 0]  # (p, m, k, K)
    moved_obs = obs[:, 1:] + com_shift(obs[:, 0], off)
    moved_pred = pred[..., 1:] + com_shift(pred[..., 0], off)
    shift_res = moved_obs - moved_pred  # (p, m, k, K, 2)
    th_a = np.square(np.asarray(theta_scale, float))
    tr_a = np.square(np.asarray(translation_scale, float))
    total = _conditional_t(theta_res[..., None], th_a, tracking[0] ** 2, lam, vecs, end_var)
    total = total + _conditional_t(shift_res, tr_a, tracking[1] ** 2, lam, vecs, end_var)
    return total


def _conditional_t(res, a, b: float, lam, vecs, end_var: float):
    """Student-t log density of the residual paths ``res`` (..., K, c) given their ends.

    Covariance ``a * cov + b * I`` per component (``cov = vecs diag(lam) vecs^T``); the
    conditional of the first ``K - 1`` rows on the last: the joint's quadratic form and
    log-determinant minus the last row's.
    """
    n_comp, n_rows = res.shape[-1], res.shape[-2]
    a = np.asarray(a, float)
    var = a[..., None] * lam + b  # (..., K), or (K,) for one scale per push
    # the residuals projected on the eigenvectors: one matrix product over every hypothesis
    rows = np.moveaxis(res, -1, -2).reshape(-1, n_rows)  # (... c, K)
    if var.ndim == 1:  # one scale per push: whitened by the same matrix for every hypothesis
        proj = (rows @ (vecs / np.sqrt(var))).reshape(*res.shape[:-2], n_comp, n_rows)
        quad = np.einsum("...ck,...ck->...", proj, proj)
    else:
        proj = (rows @ vecs).reshape(*res.shape[:-2], n_comp, n_rows)  # (..., c, K)
        quad = (np.square(proj) / var[..., None, :]).sum(axis=(-2, -1))
    logdet = np.log(var).sum(axis=-1) * n_comp
    end = a * end_var + b
    quad = quad - np.square(res[..., -1, :]).sum(axis=-1) / end
    logdet = logdet - n_comp * np.log(end)
    dims = (res.shape[-2] - 1) * n_comp
    nu = STUDENT_DOF
    return -0.5 * (nu + dims) * np.log1p(np.maximum(quad, 0.0) / nu) - 0.5 * logdet

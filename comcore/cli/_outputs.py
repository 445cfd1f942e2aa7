"""What ``comcore estimate`` prints: the region's size, the text summary, what a status means."""

from __future__ import annotations

import numpy as np

import comcore
from comcore import Status

__all__ = ["STATUS_MEANINGS", "print_text", "region_summary", "status_meaning"]

#: What each status means for the user's recording (the JSON's ``status_meaning``, the text
#: output's status line; a warning on stderr for the statuses other than ``ok`` and ``wide``).
#: ``{target}`` is ``--target-radius`` in millimetres.
STATUS_MEANINGS = {
    Status.OK: "the pushes are consistent and the region is within --target-radius "
    "({target:g} mm): use the estimate",
    Status.WIDE: "the pushes are consistent, but the region is wider than --target-radius "
    "({target:g} mm): the estimate is usable, the region says how unsure it is; more pushes "
    "across the region narrow it",
    Status.INCONSISTENT: "no CoM explains the observed motions well (Alg. 2: some pushes "
    "contradict the others, and the estimate rests on the consistent ones): check the pixel "
    "frame, the sign of theta (counter-clockwise on screen is positive) and that every push "
    "started from the pose of the mask",
    Status.NO_EVIDENCE: "no push moved the object measurably: the estimate is the prior's mean",
    Status.NO_ACTIONS: "no push turned the object enough to use: the estimate is the centroid",
    Status.FLAT_HEATMAP: "the pushes do not single out a region: the estimate is the centroid",
    Status.UNCHECKED: "Alg. 1 has no test of its evidence: any motions, right or wrong, give "
    "a region",
}


def status_meaning(status, target_radius: float) -> str:
    """What ``status`` means for the user's recording, ``target_radius`` in metres.

    >>> status_meaning("wide", 0.006).startswith("the pushes are consistent, but")
    True
    """
    meaning = STATUS_MEANINGS.get(status, "the estimator could not do its job fully")
    return meaning.format(target=1000 * target_radius)


#: Where the CoM's metres are measured from: the mask's frame, not the table's.
MASK_FRAME = (
    "in the image's frame: from the centre of its top-left pixel, x right, y down "
    "(pixels times --resolution, not a position on the table)"
)


def region_summary(est: comcore.Estimate, resolution: float, credible: float) -> dict:
    """Size of the estimate's region: area, equivalent radius, bounding box; credible radius."""
    region = np.asarray(est.region)
    area = int(region.sum())
    out: dict = {"area_px": area, "radius_px": float(np.sqrt(area / np.pi))}
    if area:
        rows, cols = np.nonzero(region)
        out["bbox_px"] = [int(cols.min()), int(rows.min()), int(cols.max()), int(rows.max())]
    if est.posterior is not None:
        out["credible_radius_px"] = float(est.posterior.credible_radius_px)
        out["credible"] = credible
        out["bootstrap"] = est.posterior.bootstrap  # 0: the posterior's own region
    out["radius_m"] = out.get("credible_radius_px", out["radius_px"]) * resolution
    return out


def print_text(result: dict, est: comcore.Estimate) -> None:
    x, y = est.com
    print(
        f"CoM: ({x:.2f}, {y:.2f}) px (column, row) = ({est.com_m[0]:.4f}, "
        f"{est.com_m[1]:.4f}) m {MASK_FRAME}"
    )
    if "com_object_m" in result:
        ox, oy = result["com_object_m"]
        print(
            f"CoM in the object's frame (the outline's, of --object-topic): ({ox:.4f}, {oy:.4f}) m"
        )
    n_kept = result["n_pushes"] - len(result["dropped_lines"])
    print(
        f"method {result['method']}, status {result['status']}, {len(est.used)} of {n_kept} "
        "pushes used"
    )
    print(f"status {result['status']}: {result['status_meaning']}")
    width, height = (100 * v for v in result["object_size_m"])
    print(
        f"object: {width:.1f} x {height:.1f} cm at {result['resolution']:g} m per pixel "
        "(check it: a wrong --resolution shows here)"
    )
    region = result["region"]
    if "credible_radius_px" in region:
        bagged = f" (bagged: {region['bootstrap']} resamplings of the pushes)"
        print(
            f"{100 * region['credible']:.0f} % credible region: {region['area_px']} px, radius "
            f"{region['credible_radius_px']:.2f} px = {region['radius_m'] * 1000:.1f} mm"
            + (bagged if region.get("bootstrap") else "")
        )
    else:
        print(f"CoM region: {region['area_px']} px (radius {region['radius_m'] * 1000:.1f} mm)")
    if result["n_frames"]:
        n_read = result["n_frames"]
        n_dropped = sum(len(p["frames"]) for p in result["dropped_frames"])
        print(
            f"frames: {n_read} read, {n_read - n_dropped} scored along their pushes, "
            f"{n_dropped} not (the JSON's dropped_frames says which and why)"
        )
    if result["used_lines"]:
        drawn = ", as the overlay numbers them" if result["overlay"] is not None else ""
        print(
            f"pushes used (CSV lines, in order{drawn}): "
            + ", ".join(map(str, result["used_lines"]))
        )
    if result["overlay"] is not None:
        replaced = " (replaced the existing file)" if result["overlay_replaced"] else ""
        print(f"overlay: {result['overlay']}{replaced}")

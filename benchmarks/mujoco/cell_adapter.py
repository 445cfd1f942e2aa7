import numpy as np

import comcore


class CellAdapter:
    """Your cell for comcore: camera frames in, masks on the table, pushes in metres out."""

    def __init__(self, clicks_px, table_m, empty_frames, work_area_m, object_box_m):
        calibration = comcore.calibrate_table(clicks_px, table_m)  # once: four or more points
        self.view = calibration.view(work_area_m, resolution=0.001)  # top-down, 1 mm a pixel
        self.empty = [self.view.rectify(frame) for frame in empty_frames]  # the arm away
        (x0, y0), (x1, y1) = self.view.pixels_from_table(np.reshape(object_box_m, (2, 2)))
        self.box = (x0, y1, x1, y0)  # where the object is, top-down pixels (row 0 is far)

    def mask(self, frame, reach=60):
        """The object's mask in the top-down image, looked for in a box that follows it."""
        (h, w), (x0, y0, x1, y1) = self.view.shape, np.round(self.box).astype(int)
        m = reach + max(x1 - x0, y1 - y0) // 2  # a push's travel (px) and the object's turn
        roi = (max(x0 - m, 0), max(y0 - m, 0), min(x1 + m, w), min(y1 + m, h))
        top = self.view.rectify(frame)
        mask = comcore.mask_from_image(
            top, background=self.empty, roi=roi, resolution=self.view.resolution
        )
        rows, cols = np.nonzero(mask.data)
        self.box = (cols.min(), rows.min(), cols.max() + 1, rows.max() + 1)
        return mask

    def arm_push(self, action):
        """A session's push (top-down pixels) in the arm's metres: (sx, sy, ex, ey)."""
        return self.view.robot_pushes([action])[0]


def find_com(cell, camera, arm, pusher_radius, rng=None, max_steps=30):
    """One session: ``camera()`` gives a frame, ``arm(push_m)`` pushes (False: it could not)."""
    first = cell.mask(camera())
    session = comcore.ActiveSession(first, pusher_radius=pusher_radius, rng=rng)
    for _ in range(max_steps):
        if session.done:
            break
        if not arm(cell.arm_push(session.next_push())):
            session.observe(failed=True)  # out of reach, a collision: nothing moved
            continue
        try:
            session.observe(cell.mask(camera()))
        except ValueError:  # the frame refused (comcore.ImageError): the push taught nothing
            session.observe(failed=True)
            try:  # but the object moved: find it again, or stop with what was learned
                session.reset_pose(comcore.measure_motion(first, cell.mask(camera())).motion)
            except ValueError:
                break
    return session.estimate()  # .com in the first mask's pixels: cell.view.table_from_pixels

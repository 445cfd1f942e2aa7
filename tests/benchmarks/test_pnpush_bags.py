"""benchmarks/realdata/pnpush_bags.py, run as a user runs it, on a bag laid out as pnpush's.

One push of a steel block (the kinematics made up: the block slides with the tip and turns),
its Vicon pose in ``/objworld`` and the tip's in the robot's frame with no frame_id, the
frames linked by ``/tf`` as in pnpush's bags (``map`` -> ``/viconworld`` -> ``/objworld``).
"""

import numpy as np
import pytest

from tests.scripts import run_script

HALF = 0.049475  # SteelBlock.stl's half side
RADIUS = 0.00475
VICON = "/vicon/SteelBlock/SteelBlock"


def write_folder(folder, trimesh):
    from tests import bags

    box = trimesh.creation.box(extents=(2 * HALF, 2 * HALF, 0.00947))
    box.export(folder / "SteelBlock.stl")
    n = 300  # 3 s at 100 Hz: the tip 2 cm below the face, then 4 cm up, pushing from 1 s
    t = np.arange(n) / 100
    tip_y = -HALF - RADIUS - 0.02 + 0.02 * np.clip(t, 0, 1) + 0.03 * np.clip(t - 1, 0, None) / 1.5
    pushing = 0.03 * np.clip(t - 1, 0, None) / 1.5  # metres the block has moved
    start = 1_438_625_711 * 10**9
    with bags.BagWriter(folder / "St_block_Test_st_1.bag", "rosbag1") as w:
        for k in range(n):
            ns = start + k * 10**7
            yaw = 2.0 * pushing[k]
            w.write(VICON, "geometry_msgs/msg/TransformStamped", ns + 10**6, w.transform_stamped(
                ns, "/objworld", VICON[1:], -0.4, pushing[k], bags.quaternion_z(yaw)))  # fmt: skip
            w.write("/tip_pose", "geometry_msgs/msg/PoseStamped", ns + 2 * 10**6, w.message(
                "geometry_msgs/msg/PoseStamped", ns, "", "", 0.01, tip_y[k], bags.DOWN))  # fmt: skip
            if k % 10 == 0:
                for parent, child, x in (
                    ("map", "/viconworld", 0.4),
                    ("/viconworld", "/objworld", 0.0),
                ):
                    msg = w.types["tf2_msgs/msg/TFMessage"](transforms=[w.transform_stamped(
                        ns, parent, child, x, 0.0, (0.0, 0.0, 0.0, 1.0))])  # fmt: skip
                    w.write("/tf", "tf2_msgs/msg/TFMessage", ns + 3 * 10**6, msg)


def test_the_pnpush_script_on_a_bag_laid_out_as_theirs(tmp_path):
    pytest.importorskip("rosbags")
    pytest.importorskip("shapely")
    trimesh = pytest.importorskip("trimesh")
    write_folder(tmp_path, trimesh)
    out = run_script("benchmarks/realdata/pnpush_bags.py", str(tmp_path))
    assert "SteelBlock.stl's footprint: [0.09895, 0.09895] m" in out
    line = next(s for s in out.splitlines() if s.startswith("St_block_Test_st_1:"))
    assert "TransformStamped 300 at 100.0 Hz in '/objworld'" in line
    assert "/tip_pose 300 at 100.0 Hz in ''" in line
    assert "pushes as recorded: none (the pusher (topic '/tip_pose') never comes" in line
    assert "/objworld in map at (0.4000, 0.0000) m" in line
    # the tip's centre touches the face: half the side plus the tip's radius (as the block
    # turns, the tip's point on the face moves off its axis)
    distance = float(line.split("the tip's centre is ")[1].split()[0])
    assert distance == pytest.approx(1000 * (HALF + RADIUS), abs=0.5)
    assert "contacts in map with the steel block's outline: 1" in line
    assert "1 pushes kept, 0 skipped" in out
    assert "estimate_posterior (limit surface): status" in out
    assert "estimate_posterior (Voting Theorem alone): status" in out

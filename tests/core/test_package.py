import subprocess
import sys

import comcore

HEAVY = (
    "torch",
    "pymunk",
    "trimesh",
    "cv2",
    "matplotlib",
    "shapely",
    "dask",
    "h5py",
    "rosbags",
    "mujoco",
    "pyarrow",
    "tqdm",
    "predictors",
    "simulators",
)


def test_import_comcore_loads_only_numpy_and_scipy():
    code = f"import sys, comcore, comcore.vt; print([m for m in {HEAVY!r} if m in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_public_names_are_exported():
    for name in comcore.__all__:
        assert hasattr(comcore, name), name
    assert comcore.vt.region is comcore.vt._voting.region

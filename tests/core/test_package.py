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


def test_every_skip_on_a_missing_module_names_the_extra_that_installs_it():
    import re
    from pathlib import Path

    import conftest

    root = Path(conftest.__file__).parent
    skipped_on = set()
    for path in (root / "tests").rglob("*.py"):
        skipped_on |= set(re.findall(r'importorskip\(\s*"([\w.]+)"', path.read_text()))
    assert skipped_on, "no importorskip found: the scan is broken"
    unnamed = sorted(m for m in skipped_on if m.split(".")[0] not in conftest.EXTRA_OF)
    assert unnamed == [], f"add these modules' extras to conftest.EXTRA_MODULES: {unnamed}"
    reason = "Skipped: could not import 'pymunk': No module named 'pymunk'"
    assert conftest.with_extra(reason).endswith("pip install comcore[sim]")
    assert conftest.with_extra("could not import 'torch.nn': x").endswith("comcore[anp]")

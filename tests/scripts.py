"""Run a script of benchmarks/ (or docs/) as a subprocess, the way a user would."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_script(path: str, *args: str, timeout: float = 300) -> str:
    """Run ``python <path> <args>`` from the repository root with only the repo on the path.

    Returns its stdout; a non-zero exit fails the test with the script's stderr.
    """
    out = subprocess.run(
        [sys.executable, str(ROOT / path), *args],
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), "PATH": ""},
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert out.returncode == 0, out.stderr
    return out.stdout

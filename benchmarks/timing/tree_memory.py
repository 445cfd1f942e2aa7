"""Sample the summed resident memory of a process and all its descendants until it exits.

    python benchmarks/timing/tree_memory.py PID [INTERVAL_S]   -> prints the peak in MiB at the end

GNU time's "Maximum resident set size" is the peak of the largest single process; with
worker processes the machine needs their sum, which this measures (Linux /proc only).
"""

from __future__ import annotations

import os
import sys
import time


def children(pid: int) -> list[int]:
    out = []
    for task in os.listdir(f"/proc/{pid}/task"):
        try:
            with open(f"/proc/{pid}/task/{task}/children") as f:
                out += [int(c) for c in f.read().split()]
        except OSError:
            pass
    return out


def tree_rss_kib(pid: int) -> int:
    total, stack = 0, [pid]
    while stack:
        p = stack.pop()
        try:
            with open(f"/proc/{p}/status") as f:
                total += next(int(line.split()[1]) for line in f if line.startswith("VmRSS:"))
            stack += children(p)
        except (OSError, StopIteration):
            pass
    return total


def main() -> None:
    pid = int(sys.argv[1])
    interval = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    peak = 0
    while os.path.exists(f"/proc/{pid}"):
        peak = max(peak, tree_rss_kib(pid))
        time.sleep(interval)
    print(f"peak summed RSS of the process tree: {peak / 1024:.0f} MiB")


if __name__ == "__main__":
    main()

#!/usr/bin/env bash
# The full benchmark of docs/results/paper.md: 20 objects x 300 trials x 2 friction classes, oracle
# predictor. Measures the wall time and peak memory with GNU time (largest single process)
# and benchmarks/timing/tree_memory.py (main process + workers, summed).
# Usage: benchmarks/accuracy/run_full.sh [OUT_DIR] [extra comcore bench options]
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-bench-out/full}"
shift || true
mkdir -p "$out"
PYTHONPATH=. /usr/bin/time -v -o "$out/time.txt" \
    nice -n 10 python -m comcore bench --trials 300 --friction both --predictor oracle \
    --workers 2 --seed 0 --out "$out" "$@" 2> "$out/stderr.txt" > "$out/stdout.txt" &
timer=$!
sleep 2
python benchmarks/timing/tree_memory.py "$(pgrep -P "$timer" | head -1)" 2 > "$out/tree_memory.txt" &
wait "$timer"
wait
grep -E "Elapsed|Maximum resident" "$out/time.txt"
cat "$out/tree_memory.txt"

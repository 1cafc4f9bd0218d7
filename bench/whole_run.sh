#!/usr/bin/env bash
# Times whole propagation runs: runs `propagate SCENE ARGS...` REPEAT times (default 3)
# and prints the median of each phase of the JSON report (wall seconds per phase, which add
# up to the total; CPU seconds summed over worker threads inside the passes) and the peak
# RSS.
# Usage: bench/whole_run.sh [-r REPEAT] [-b BUILD] SCENE [propagate options...]
set -euo pipefail
repeat=3
build=build
while getopts "r:b:" opt; do
  case $opt in
    r) repeat=$OPTARG ;;
    b) build=$OPTARG ;;
    *) echo "usage: $0 [-r REPEAT] [-b BUILD] SCENE [propagate options...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { echo "usage: $0 [-r REPEAT] [-b BUILD] SCENE [propagate options...]" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for i in $(seq 1 "$repeat"); do
  "$build/propagate/propagate" "$@" -q -o "$work/run.vlf" --report "$work/report-$i.json" > /dev/null
done
python3 - "$work" "$repeat" <<'PY'
import json, statistics, sys
work, n = sys.argv[1], int(sys.argv[2])
reports = [json.load(open(f"{work}/report-{i}.json")) for i in range(1, n + 1)]
keys = ["total", "setup", "passes", "specular", "filter", "bookkeeping", "resample", "write", "other"]
cpu_keys = ["rasterise", "clipping", "exchange", "transfer"]
med = {k: statistics.median(r["timings_s"][k] for r in reports) for k in keys}
med.update({k: statistics.median(r["timings_s"]["cpu_in_passes"][k] for r in reports) for k in cpu_keys})
rss = statistics.median(r["memory_bytes"]["peak_rss"] for r in reports)
totals = ", ".join(f"{r['timings_s']['total']:.2f}" for r in reports)
print(f"runs: {n}  total (wall) s: {totals}  median {med['total']:.3f}")
print("median wall s per phase: " + "  ".join(f"{k} {med[k]:.3f}" for k in keys[1:]))
print("median CPU s inside the passes (summed over threads): " +
      "  ".join(f"{k} {med[k]:.3f}" for k in cpu_keys))
print(f"median peak RSS: {rss / 2**20:.1f} MiB")
err = max(e["relative_error"] for r in reports for e in r["ledger"])
print(f"worst ledger balance error: {err:.2e}")
PY

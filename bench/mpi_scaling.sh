#!/usr/bin/env bash
# MPI strong scaling on this machine (issue 13, BENCHMARKS.md "MPI"): runs
# `propagate SCENE ARGS...` REPEAT times (default 3) as one process and as
# `mpirun -np K` for each K given with -k (default "2"), and prints per K the median wall
# time (total and passes), the slowest rank's pass time against the mean (imbalance), the
# bytes each rank sent per cycle, each rank's peak RSS, and whether the bake's files are
# byte-identical to the single process's.
# Usage: bench/mpi_scaling.sh [-r REPEAT] [-b BUILD] [-k "2 3"] [-t THREADS] SCENE [options...]
#   -t: --threads per rank (and for the single process); default: all cores each.
set -euo pipefail
repeat=3 build=build ks="2" threads=0
while getopts "r:b:k:t:" opt; do
  case $opt in
    r) repeat=$OPTARG ;;
    b) build=$OPTARG ;;
    k) ks=$OPTARG ;;
    t) threads=$OPTARG ;;
    *) echo "usage: $0 [-r REPEAT] [-b BUILD] [-k \"2 3\"] [-t THREADS] SCENE [options...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ $# -ge 1 ] || { echo "usage: $0 [-r REPEAT] [-b BUILD] [-k \"2 3\"] SCENE [options...]" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prop="$build/propagate/propagate"
for i in $(seq 1 "$repeat"); do
  "$prop" "$@" --threads "$threads" -q -o "$work/k1.vlf" --report "$work/k1-$i.json" > /dev/null
  for k in $ks; do
    mpirun --allow-run-as-root --oversubscribe -np "$k" "$prop" "$@" --threads "$threads" -q \
      -o "$work/k$k.vlf" --report "$work/k$k-$i.json" > /dev/null
  done
done
for k in $ks; do
  for f in lightmaps.exr lightfield.exr; do
    cmp -s "$work/k1.vlf/$f" "$work/k$k.vlf/$f" || echo "K=$k: $f DIFFERS from the single process's"
  done
done
python3 - "$work" "$repeat" "1 $ks" <<'PY'
import json, statistics, sys
work, n, ks = sys.argv[1], int(sys.argv[2]), sys.argv[3].split()
for k in ks:
    reps = [json.load(open(f"{work}/k{k}-{i}.json")) for i in range(1, n + 1)]
    tot = [r["timings_s"]["total"] for r in reps]
    line = (f"K={k}: total s {', '.join(f'{t:.2f}' for t in tot)} median {statistics.median(tot):.2f}"
            f"  passes median {statistics.median(r['timings_s']['passes'] for r in reps):.2f}")
    if "ranks" in reps[0]:
        imb = statistics.median(r["ranks"]["imbalance"] for r in reps)
        per = reps[0]["ranks"]["per_rank"]
        sent = [p["bytes_sent"] / max(1, p["cycles_run"]) / 2**20 for p in per]
        rss = [statistics.median(r["ranks"]["per_rank"][q]["peak_rss"] for r in reps) / 2**20
               for q in range(len(per))]
        cache = [p["geometry_cache_bytes"] / 2**20 for p in per]
        line += (f"  imbalance {imb:.3f}  MiB sent per cycle by rank: "
                 + " ".join(f"{s:.2f}" for s in sent)
                 + "  peak RSS MiB: " + " ".join(f"{m:.0f}" for m in rss)
                 + "  geometry cache MiB: " + " ".join(f"{c:.0f}" for c in cache))
    else:
        line += f"  peak RSS MiB {statistics.median(r['memory_bytes']['peak_rss'] for r in reps) / 2**20:.0f}"
        line += f"  geometry cache MiB {reps[0]['memory_bytes']['geometry_cache'] / 2**20:.0f}"
    print(line)
PY

#!/usr/bin/env bash
# How propagation scales with the triangle count: the same model at 1k, 4k, 16k, 64k, 256k
# and 1M triangles, propagated with the same field, one run each, into a Markdown table of
# triangles, phase times, wall time, peak RSS and bake size.
#   model series (default): scenes/meshes/stanford-bunny-1k.obj (1,000 triangles) split
#     1-to-4 by bench/subdivide_mesh.py 0..MAX times (the surface stays the same), placed
#     as in scenes/bunny.json (the empty Cornell box, 6 more faces)
#   floor series (-f): scenes/floor-quad.json whose floor is 1000 * 4^k random triangles
#     covering the same quad (bench/make_triangulated_floor.py)
# Each run: /usr/bin/time -v build/propagate/propagate SCENE -l 513 -N 64 -m 8 -c 4 -q -o OUT
# --report R.json --no-surfaces (other propagate options, given after the flags, replace these four).
# Columns: setup = scene load + texel frames + light-field set-up; propagation = the cycles
# (passes, specular, filter, bookkeeping, resampling); gather = the final gather
# (final_gather.hpp); write = writing the bake; wall =
# /usr/bin/time's elapsed time of the whole process; RSS = its peak resident set.
# With -r R every size runs R times and each column is the median.
# Usage: bench/scale.sh [-b BUILD] [-L MAXLEVEL (default 5 = 1M)] [-f] [-r REPEAT] [-k KEEPDIR]
#                       [propagate options]
# Runs one after another under `nice`; the 1M run needs several GB of RAM and minutes.
set -euo pipefail
build=build
max=5
series=model
repeat=1
keep=
while getopts "b:L:fr:k:" opt; do
  case $opt in
    b) build=$OPTARG ;;
    L) max=$OPTARG ;;
    f) series=floor ;;
    r) repeat=$OPTARG ;;
    k) keep=$OPTARG ;;
    *) sed -n '2,/^set -euo/p' "$0" | sed '$d' >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
cd "$(dirname "$0")/.."
build=$(realpath "$build")
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(-l 513 -N 64 -m 8 -c 4)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/meshes"

echo "# bench/scale.sh ($series series, median of $repeat): propagate ${args[*]}"
echo "binary $build/propagate/propagate of $(date -r "$build/propagate/propagate" '+%F %T'),"\
  "scripts $(git describe --always --dirty 2> /dev/null || echo unknown); $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| triangles | scene faces | setup s | propagation s | gather s | write s | wall s | peak RSS MiB | bake MB |"
echo "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for level in $(seq 0 "$max"); do
  name=$series-$level
  if [ $series = model ]; then
    bench/subdivide_mesh.py scenes/meshes/stanford-bunny-1k.obj "$work/meshes/$name.obj" \
      --levels "$level" 2> "$work/gen.txt" || { cat "$work/gen.txt" >&2; exit 1; }
    # scenes/bunny.json with its mesh swapped: the scene sits in $work beside meshes/.
    sed "s|meshes/stanford-bunny.obj|meshes/$name.obj|" scenes/bunny.json > "$work/$name.json"
    grep -q "meshes/$name.obj" "$work/$name.json"
  else
    bench/make_triangulated_floor.py --triangles $((1000 * 4 ** level)) --name "$name" \
      --scene-dir "$work" 2> "$work/gen.txt" || { cat "$work/gen.txt" >&2; exit 1; }
  fi
  tris=$(grep -c '^f ' "$work/meshes/$name.obj")
  failed=
  for i in $(seq 1 "$repeat"); do
    rc=0
    /usr/bin/time -v -o "$work/$name-time-$i.txt" nice -n 19 "$build/propagate/propagate" \
      "$work/$name.json" "${args[@]}" -q -o "$work/$name.vlf" --report "$work/$name-report-$i.json" --no-surfaces \
      > "$work/log.txt" 2>&1 || rc=$?
    if [ $rc != 0 ]; then
      failed="failed (exit $rc): $(tail -n 1 "$work/log.txt")"
      break
    fi
  done
  if [ -n "$failed" ]; then
    echo "| $tris | $failed | | | | | | | |"
    rm -rf "$work/$name.vlf" "$work/meshes/$name.obj"
    continue
  fi
  bake=$(du -sb "$work/$name.vlf" | cut -f1)
  python3 - "$work/$name" "$repeat" "$tris" "$bake" <<'PY'
import json, re, statistics, sys
stem, n, tris, bake = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
rows = []
for i in range(1, n + 1):
    r = json.load(open(f"{stem}-report-{i}.json"))
    t = r["timings_s"]
    tv = open(f"{stem}-time-{i}.txt").read()
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", tv).group(1))
    hms = re.search(r"Elapsed \(wall clock\) time.*: ([\d:.]+)", tv).group(1).split(":")
    wall = sum(float(x) * 60 ** k for k, x in enumerate(reversed(hms)))
    # (propagate resamples specular maps in the bake writer: that time is in "write")
    prop = sum(t[k] for k in ("passes", "specular", "filter", "bookkeeping", "resample"))
    rows.append((t["setup"], prop, t.get("gather", 0.0), t["write"], wall, rss_kb / 1024))
    faces = r["scene"]["faces"]
med = [statistics.median(col) for col in zip(*rows)]
print(f"| {tris:,} | {faces:,} | {med[0]:.2f} | {med[1]:.2f} | {med[2]:.2f} | {med[3]:.2f} | "
      f"{med[4]:.2f} | {med[5]:.0f} | {bake / 1e6:.1f} |")
PY
  if [ -n "$keep" ]; then
    mkdir -p "$keep"
    cp "$work/$name"-report-*.json "$work/$name"-time-*.txt "$keep/"
  fi
  rm -rf "$work/$name.vlf" "$work/meshes/$name.obj"
done

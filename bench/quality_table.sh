#!/usr/bin/env bash
# The quality presets on the Cornell boxes against the path tracer (issue 9):
# propagation time (median of REPEAT runs), relative RMSE away from emitters in texture
# and raytrace modes (lookup rendered 16 x 16 per pixel like the reference's pixel
# integral), mean ratio there, worst ledger balance error and numerical loss.
#   bench/quality_table.sh [build-dir] [repeat] [presets...]
# Prints a Markdown table; BENCHMARKS.md holds the last run's.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
repeat=${2:-3}
shift $(( $# > 2 ? 2 : $# ))
presets=${*:-draft preview final}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| preset | scene | propagation s (median of $repeat) | cycles | texture | raytrace | mean ratio (texture, mean of R, G, B) | ledger error | numerical loss |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for q in $presets; do
  for scene in cornell-empty cornell cornell-mirrors; do
    for i in $(seq 1 "$repeat"); do
      "$build/propagate/propagate" "scenes/$scene.json" --quality "$q" -q -o "$work/b.vlf" \
        --report "$work/r-$i.json" > /dev/null
    done
    for mode in texture raytrace; do
      "$build/walkthrough/walkthrough" "$work/b.vlf" --mode "$mode" --size 128x128 --pixel-samples 16 \
        --reference "data/$scene-pathtrace-128.exr" -o "$work/$mode.exr" > "$work/$mode.txt"
    done
    python3 - "$work" "$repeat" "$q" "$scene" <<'PY'
import json, re, statistics, sys
work, n, q, scene = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
reports = [json.load(open(f"{work}/r-{i}.json")) for i in range(1, n + 1)]
t = statistics.median(r["timings_s"]["total"] - r["timings_s"]["write"] for r in reports)
led = reports[0]["ledger"]
err = max(e["relative_error"] for e in led)
loss = sum(led[-1]["lost"]["total"]) / sum(led[-1]["emitted"])
def away(mode):
    text = open(f"{work}/{mode}.txt").read()
    rmse = float(re.search(r"([0-9.]+) away from emitters", text).group(1))
    ratio = [float(x) for x in re.search(r"\(R G B\): ([0-9.]+) ([0-9.]+) ([0-9.]+)", text).groups()]
    return rmse, sum(ratio) / 3
tx, ratio = away("texture")
rt, _ = away("raytrace")
print(f"| {q} | {scene} | {t:.2f} | {len(led)} | {100*tx:.2f} % | {100*rt:.2f} % | {ratio:.4f} | {err:.1e} | {100*loss:.4f} % |")
PY
  done
done

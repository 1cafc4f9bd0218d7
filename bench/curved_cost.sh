#!/usr/bin/env bash
# What a curved specular object costs the propagation (issue 14's goal): the empty Cornell
# box, the same box with a mirror ball (rho_s 0.9, the glass ball's 5,120 smooth faces) and
# with the glass ball (scenes/cornell-glass.json), at the issue's settings
# -l 2049 -N 128 -m 16 -c 24 (other propagate options, given after the flags, replace them).
# R rounds (-r, default 3), each running the mirror ball and the glass ball, every ball run
# between two runs of the empty box; prints a Markdown table of the medians of wall time and
# peak RSS (/usr/bin/time), the specular gathers' time (the report's timings_s.specular),
# the ratios of the medians to the empty box's, and each round's time ratio to the mean of
# the empty runs around it, with their median.
# Usage: bench/curved_cost.sh [-b BUILD] [-r REPEAT] [-- propagate options]
set -euo pipefail
build=build
repeat=3
while getopts "b:r:" opt; do
  case $opt in
    b) build=$OPTARG ;;
    r) repeat=$OPTARG ;;
    *) sed -n '2,/^set -euo/p' "$0" | sed '$d' >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[ "$repeat" -ge 1 ] 2> /dev/null || { echo "curved_cost.sh: -r must be at least 1" >&2; exit 2; }
cd "$(dirname "$0")/.."
build=$(realpath "$build")
args=("$@")
[ ${#args[@]} -gt 0 ] || args=(-l 2049 -N 128 -m 16 -c 24)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 - "$work/mirror-ball.json" <<'EOF'
import json, sys
s = json.load(open("scenes/cornell-glass.json"))
s["materials"]["mirror"] = {"specular": [0.9, 0.9, 0.9]}
del s["materials"]["glass"]
for o in s["objects"]:
    if o["name"] == "glass ball":
        o["material"] = "mirror"
json.dump(s, open(sys.argv[1], "w"))
EOF
median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
scenes=(scenes/cornell-empty.json "$work/mirror-ball.json" scenes/cornell-glass.json)
echo "settings: ${args[*]}; $repeat rounds, medians"
echo
echo "| scene | wall s | peak RSS GB | specular gathers s | time / empty | memory / empty | time / bracketing empties, by round (median) |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | --- |"
# This machine's speed drifts by a quarter within minutes, so the scenes run in rounds (not
# each scene's runs in a row) and every curved-ball run is bracketed by runs of the empty
# box: empty, mirror ball, empty, glass ball, empty, mirror ball, ... Each ball run's ratio
# is its time over the mean of the empty runs just before and just after it, printed round
# by round with their median beside the ratio of the medians.
run() {  # scene index
  /usr/bin/time -f "%e %M" -o "$work/time" nice "$build/propagate/propagate" "${scenes[$1]}" \
    "${args[@]}" -q -o "$work/out.vlf" --report "$work/r.json" > /dev/null
  read -r t m < "$work/time"
  echo "$t" >> "$work/t$1"
  echo "$m" >> "$work/m$1"
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['timings_s']['specular'])" \
    "$work/r.json" >> "$work/s$1"
}
run 0
for _ in $(seq "$repeat"); do
  for k in 1 2; do
    run "$k"
    run 0
  done
done
# Empty runs 1, 2, 3, ...: mirror run r sits between empty runs 2r - 1 and 2r, glass run r
# between 2r and 2r + 1.
for k in "${!scenes[@]}"; do
  t=$(median < "$work/t$k")
  m=$(median < "$work/m$k")
  s=$(median < "$work/s$k")
  [ "$k" -gt 0 ] || { base_t=$t; base_m=$m; }
  if [ "$k" -eq 0 ]; then
    rounds="1"
  else
    rounds=$(awk -v k="$k" 'NR == FNR {e[FNR] = $1; next}
      {a = e[2 * FNR - 2 + k]; b = e[2 * FNR - 1 + k]; printf "%.2f\n", $1 / ((a + b) / 2)}' \
      "$work/t0" "$work/t$k" > "$work/r$k"
      paste -sd ' ' "$work/r$k" | sed 's| | / |g')
    rounds="$rounds ($(median < "$work/r$k"))"
  fi
  awk -v n="$(basename "${scenes[$k]}")" -v t="$t" -v m="$m" -v s="$s" -v bt="$base_t" \
    -v bm="$base_m" -v r="$rounds" \
    'BEGIN {printf "| %s | %.1f | %.2f | %.1f | %.2f | %.1f | %s |\n", n, t, m / 1048576, s, t / bt, m / bm, r}'
done

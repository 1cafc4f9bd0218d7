#!/usr/bin/env bash
# What a curved specular object costs the propagation (issue 14's goal): the empty Cornell
# box, the same box with a mirror ball (rho_s 0.9, the glass ball's 5,120 smooth faces) and
# with the glass ball (scenes/cornell-glass.json), at the issue's settings
# -l 2049 -N 128 -m 16 -c 24 (other propagate options, given after the flags, replace them).
# R rounds (-r, default 3), each running the three scenes one after the other; prints a
# Markdown table of the medians of wall time and peak RSS (/usr/bin/time), the specular
# gathers' time (the report's timings_s.specular), the ratios to the empty box, and each
# round's time ratio.
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
echo "settings: ${args[*]}; $repeat rounds of the three scenes, medians"
echo
echo "| scene | wall s | peak RSS GB | specular gathers s | time / empty | memory / empty | time / empty by round |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | --- |"
# Rounds of the three scenes one after the other (not each scene's runs in a row): this
# machine's speed drifts by a quarter within minutes, and a drift then moves every scene of
# a round alike. Each round's ratios are printed beside the medians.
for _ in $(seq "$repeat"); do
  for k in "${!scenes[@]}"; do
    /usr/bin/time -f "%e %M" -o "$work/time" nice "$build/propagate/propagate" "${scenes[$k]}" \
      "${args[@]}" -q -o "$work/out.vlf" --report "$work/r.json" > /dev/null
    read -r t m < "$work/time"
    echo "$t" >> "$work/t$k"
    echo "$m" >> "$work/m$k"
    python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['timings_s']['specular'])" \
      "$work/r.json" >> "$work/s$k"
  done
done
for k in "${!scenes[@]}"; do
  t=$(median < "$work/t$k")
  m=$(median < "$work/m$k")
  s=$(median < "$work/s$k")
  [ "$k" -gt 0 ] || { base_t=$t; base_m=$m; }
  rounds=$(paste -d ' ' "$work/t$k" "$work/t0" | awk '{printf "%s%.2f", (NR > 1 ? " / " : ""), $1 / $2}')
  awk -v n="$(basename "${scenes[$k]}")" -v t="$t" -v m="$m" -v s="$s" -v bt="$base_t" \
    -v bm="$base_m" -v r="$rounds" \
    'BEGIN {printf "| %s | %.1f | %.2f | %.1f | %.2f | %.1f | %s |\n", n, t, m / 1048576, s, t / bt, m / bm, r}'
done

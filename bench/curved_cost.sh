#!/usr/bin/env bash
# What a curved specular object costs the propagation (issue 14's goal): the empty Cornell
# box, the same box with a mirror ball (rho_s 0.9, the glass ball's 5,120 smooth faces) and
# with the glass ball (scenes/cornell-glass.json), at the issue's settings
# -l 2049 -N 128 -m 16 -c 24 (other propagate options, given after the flags, replace them).
# Each scene runs R times (-r, default 3); prints a Markdown table of the medians of wall time
# and peak RSS (/usr/bin/time), the specular gathers' time (the report's timings_s.specular)
# and the ratios to the empty box.
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
echo "settings: ${args[*]}; $repeat runs each, medians"
echo
echo "| scene | wall s | peak RSS GB | specular gathers s | time / empty | memory / empty |"
echo "| --- | ---: | ---: | ---: | ---: | ---: |"
base_t=
base_m=
for scene in scenes/cornell-empty.json "$work/mirror-ball.json" scenes/cornell-glass.json; do
  : > "$work/t"
  : > "$work/m"
  : > "$work/s"
  for _ in $(seq "$repeat"); do
    /usr/bin/time -f "%e %M" -o "$work/time" nice "$build/propagate/propagate" "$scene" \
      "${args[@]}" -q -o "$work/out.vlf" --report "$work/r.json" > /dev/null
    read -r t m < "$work/time"
    echo "$t" >> "$work/t"
    echo "$m" >> "$work/m"
    python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['timings_s']['specular'])" \
      "$work/r.json" >> "$work/s"
  done
  t=$(median < "$work/t")
  m=$(median < "$work/m")
  s=$(median < "$work/s")
  [ -n "$base_t" ] || { base_t=$t; base_m=$m; }
  awk -v n="$(basename "$scene")" -v t="$t" -v m="$m" -v s="$s" -v bt="$base_t" -v bm="$base_m" \
    'BEGIN {printf "| %s | %.1f | %.2f | %.1f | %.1f | %.1f |\n", n, t, m / 1048576, s, t / bt, m / bm}'
done

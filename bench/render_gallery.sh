#!/usr/bin/env bash
# Propagates every scene of scenes/ (and scenes/complexity/) and renders its cameras in raytrace mode into
# docs/gallery/<scene>[-<camera>].png, so a reader sees what the engine does; the settings
# of every picture are written beside them into docs/gallery/README.md.
#   most scenes:        l = 513,  N = 64,  m = 8,  6 cycles, 3 perturbations, sigma = 0.7
#   $fine_scenes:       l = 2049, N = 128, m = 16 (the paper's Figs. 13, 14: l = 2049, N = 256)
# Views in $references are also path-traced as an unbiased reference.
# About 5 minutes on the 2-core machine.
# Usage: bench/render_gallery.sh [-b BUILD]
set -euo pipefail
build=build
[ "${1:-}" = "-b" ] && build=$2
cd "$(dirname "$0")/.."
common=(--cycles 6 --perturbations 3 --filter-sigma 0.7)
base=(--directions 513 --resolution 64 --tile 8)
fine=(--directions 2049 --resolution 128 --tile 16)
fine_scenes=" ring caustic "      # the caustic scenes, at the finer field
references=" ring:top "           # scene:camera views also path-traced (4096 spp, 256x256)
mkdir -p docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
notes="$work/README.md"
{
  echo "# Gallery"
  echo
  echo "Made by \`bench/render_gallery.sh\` (build of \`$(git describe --always --dirty 2> /dev/null || echo unknown)\`):"
  echo "each scene propagated with the settings below, then rendered in \`raytrace\` mode (VLF §6.3:"
  echo "diffuse surfaces by P^T lookup, mirrors by recursive reflection), 512×512, exposure 0."
  echo
  echo "| picture | scene | propagate settings | propagation (s) |"
  echo "| --- | --- | --- | ---: |"
} > "$notes"
for file in scenes/*.json scenes/complexity/*.json; do
  scene=${file#scenes/}
  scene=${scene%.json}
  name=$(basename "$scene")
  field=("${base[@]}")
  [[ $fine_scenes == *" $name "* ]] && field=("${fine[@]}")
  t0=$(date +%s.%N)
  "$build/propagate/propagate" "scenes/$scene.json" "${field[@]}" "${common[@]}" -q -o "$work/$name.vlf" > /dev/null
  secs=$(python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$t0" "$(date +%s.%N)")
  cams=$(python3 -c "import json,sys; print(' '.join(c['name'] for c in json.load(open(sys.argv[1])).get('cameras', [])))" "scenes/$scene.json")
  first=1
  for cam in $cams; do
    out=$name.png
    [ $first = 1 ] || out=$name-$cam.png
    first=0
    "$build/walkthrough/walkthrough" "$work/$name.vlf" --camera "$cam" --mode raytrace --size 512x512 \
        -o "docs/gallery/$out" | tail -n 1
    echo "| ![$name $cam]($out) \`$out\` | \`scenes/$scene.json\`, camera \`$cam\` | \`${field[*]} ${common[*]}\` | $secs |" >> "$notes"
    if [[ $references == *" $name:$cam "* ]]; then
      # The caustic against the unbiased reference of the same scene and camera.
      ref=$name-$cam-pathtrace.png
      "$build/walkthrough/walkthrough" "$work/$name.vlf" --camera "$cam" --mode pathtrace --spp 4096 \
          --size 256x256 -o "docs/gallery/$ref" | tail -n 1
      echo "| ![$name $cam pathtrace]($ref) \`$ref\` | the same, \`--mode pathtrace --spp 4096\`, 256×256: the reference | — | — |" >> "$notes"
    fi
  done
done
cp "$notes" docs/gallery/README.md
echo "gallery: docs/gallery/*.png, settings in docs/gallery/README.md"

#!/usr/bin/env bash
# MPI ranks (issue 13, docs/cluster.md), run by ctest when propagate is built with VLF_MPI:
#   identical  mpirun -np 2 and -np 3 (3 does not divide l) and -np 4 give a bake whose
#              files are byte-identical to the single process's, on a scene with mirrors,
#              perturbation and the filter, on one with point and spot lights and (2
#              ranks) on one with smooth glass; so do 4 ranks with --chunks 5; more ranks
#              than chunks are refused;
#   killed     one rank of a 2-rank job is killed after the first checkpoint: the job
#              ends (no hang) with a message naming the rank, and the resumed job gives
#              the single process's bake.
# Usage: mpi_ranks_test.sh identical|killed MPIEXEC PROPAGATE SOURCE_DIR WORK_DIR
set -euo pipefail
mode=$1 mpiexec=$2 propagate=$3 src=$4 work=$5
rm -rf "$work"
mkdir -p "$work"
cd "$work"
mpirun=("$mpiexec" --allow-run-as-root --oversubscribe)

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# The bundle's files, byte for byte (the manifest also holds timings: its checksums of the
# other files are compared through the files themselves).
same_bake() {
  for f in scene.json geometry.bin textures.bin lightmaps.exr lightfield.exr; do
    [ -f "$1/$f" ] || [ ! -f "$2/$f" ] || fail "$1/$f missing"
    [ -f "$1/$f" ] || continue
    cmp -s "$1/$f" "$2/$f" || fail "$1/$f differs from $2/$f"
  done
}

case $mode in
identical)
  mirrors=("$src/tests/scenes/closed-mirror-room.json" -l 129 -N 32 -m 8 -c 3
           --perturbations 1 --filter-sigma 0.7 -q)
  "$propagate" "${mirrors[@]}" -o one.vlf > /dev/null
  for np in 2 3 4; do
    "${mpirun[@]}" -np $np "$propagate" "${mirrors[@]}" -o np$np.vlf --report np$np.json \
      > np$np.log
    grep -q '"per_rank"' np$np.json || fail "report of -np $np has no per_rank timings"
    grep -q "\"rank\": $((np - 1))" np$np.json || fail "report of -np $np lacks rank $((np - 1))"
    same_bake np$np.vlf one.vlf
  done
  # Another chunk count is another bake, the same on any number of ranks up to it.
  "$propagate" "${mirrors[@]}" --chunks 5 -o c5.vlf > /dev/null
  "${mpirun[@]}" -np 4 "$propagate" "${mirrors[@]}" --chunks 5 -o c5np4.vlf > /dev/null
  same_bake c5np4.vlf c5.vlf
  if "${mpirun[@]}" -np 3 "$propagate" "${mirrors[@]}" --chunks 2 -o few.vlf > /dev/null \
    2> few.err; then
    fail "3 ranks for 2 chunks were not refused"
  fi
  grep -q "more ranks than --chunks 2" few.err || fail "no clear refusal: $(cat few.err)"
  lights=("$src/tests/scenes/lights-open-room.json" -l 33 -N 16 -m 4 -c 2 -q)
  "$propagate" "${lights[@]}" -o lights1.vlf > /dev/null
  "${mpirun[@]}" -np 3 "$propagate" "${lights[@]}" -o lights3.vlf > /dev/null
  same_bake lights3.vlf lights1.vlf
  # Smooth glass: the smooth surfaces' sources (surface_specular.hpp) cross ranks.
  glass=("$src/tests/scenes/glass-room.json" -l 129 -N 32 -m 8 -c 3 -q)
  "$propagate" "${glass[@]}" -o glass1.vlf > /dev/null
  "${mpirun[@]}" -np 2 "$propagate" "${glass[@]}" -o glass2.vlf > /dev/null
  same_bake glass2.vlf glass1.vlf
  ;;
killed)
  args=("$src/tests/scenes/closed-mirror-room.json" -l 513 -N 64 -m 8 -c 4 -q)
  "$propagate" "${args[@]}" -o one.vlf > /dev/null
  "${mpirun[@]}" -np 2 "$propagate" "${args[@]}" -o two.vlf --checkpoint ckpt \
    > run.log 2> run.err &
  job=$!
  for _ in $(seq 1 1200); do
    [ -f ckpt/manifest.json ] && break
    sleep 0.05
  done
  [ -f ckpt/manifest.json ] || fail "no checkpoint after 60 s"
  # The ranks are mpirun's children on one node; kill rank 1's process (the second).
  ranks=($(pgrep -P $job || true))
  [ ${#ranks[@]} -eq 2 ] || fail "expected 2 rank processes under mpirun, found ${#ranks[@]}"
  kill -KILL "${ranks[1]}"
  rc=0
  wait $job || rc=$?
  [ $rc -ne 0 ] || fail "the job ended with 0 after a rank was killed"
  [ ! -e two.vlf ] || fail "a killed job left a bake"
  grep -q "rank" run.err || fail "no message naming a rank: $(cat run.err)"
  cycle=$(sed -n 's/.*"cycle": \([0-9]*\).*/\1/p' ckpt/manifest.json)
  [ "$cycle" -ge 1 ] && [ "$cycle" -lt 4 ] || fail "checkpoint after cycle $cycle"
  echo "killed after cycle $cycle's checkpoint; stderr:"
  grep -i "rank" run.err | head -5
  "${mpirun[@]}" -np 2 "$propagate" "${args[@]}" -o two.vlf --resume ckpt --checkpoint ckpt \
    > resume.log
  grep -q "resuming   ckpt after cycle" resume.log || fail "resume did not say where it resumed"
  same_bake two.vlf one.vlf
  ;;
*)
  fail "unknown mode $mode"
  ;;
esac
echo "mpi $mode: ok"

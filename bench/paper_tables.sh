#!/usr/bin/env bash
# Reproduces the scalability experiments of the paper's §7 (Khanna et al., VLF) with the
# propagate executable and writes the results -- tables with the paper's figures beside
# ours as ratios, and PNG plots -- into BENCHMARKS.md between the markers
# `<!-- paper-tables:begin -->` and `<!-- paper-tables:end -->` and into docs/bench/*.png.
#
# Series (all 4 cycles, octahedral directions, every other option at its default):
#   directions  scenes/office.json, N = 64, m = 8, l = 9, 33, 129, 513, 2049, 8193
#   tiles       scenes/office.json, N = 64, l = 513, n = 1x1 ... 32x32 tiles (m = 64 ... 2),
#               plus fragments per tile (mean +- sd) from --dry-run
#   polygons    scenes/complexity/complexity-<faces>.json (bench/make_complexity_scene.py),
#               224 ... 1736 faces, l = 513, N = 64, m = 8
#   fig12       scenes/cornell-mirrors.json, N = 128, m = 16, l = 2049
# Each configuration is run 3 times and the median reported; a configuration whose first
# run takes longer than 60 s is run once (the tables say how many runs each figure is).
#
# --quick (under 5 minutes on the 2-core machine): l up to 513, tiles at l = 129, the three
# smallest complexity scenes, Fig. 12 at l = 513, N = 64, m = 8. The tables say "quick".
# The full series is estimated at 11-15 min on the shared 2-core machine (l = 8193 about
# 1.5 min and 2.5 GB, Fig. 12 about 1.5 min and 2 GB, one run each).
#
# Usage: bench/paper_tables.sh [--quick] [-b BUILD_DIR] [-t THREADS] [-r REPEAT]
# Progress goes to stderr. Needs python3 and gnuplot (pngcairo or png terminal).
set -euo pipefail

quick=0
build=build
threads=0
repeat=3
long_s=60
usage() { echo "usage: $0 [--quick] [-b BUILD_DIR] [-t THREADS] [-r REPEAT]" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --quick) quick=1 ;;
    -b) [ $# -ge 2 ] || usage; build=$2; shift ;;
    -t) [ $# -ge 2 ] || usage; threads=$2; shift ;;
    -r) [ $# -ge 2 ] || usage; repeat=$2; shift ;;
    -h|--help) sed -n '2,23p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) usage ;;
  esac
  shift
done

root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
prop=$build/propagate/propagate
[ -x "$prop" ] || { echo "$0: $prop not found (run 'make build')" >&2; exit 2; }
command -v gnuplot > /dev/null || { echo "$0: gnuplot not found" >&2; exit 2; }
grep -q '<!-- paper-tables:begin -->' BENCHMARKS.md && grep -q '<!-- paper-tables:end -->' BENCHMARKS.md ||
  { echo "$0: BENCHMARKS.md lacks the paper-tables markers" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$(date +%s)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
log() { printf '[paper-tables %s +%ds] %s\n' "$(date +%H:%M:%S)" $(($(date +%s) - start)) "$*" >&2; }
total_of() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["timings_s"]["total"])' "$1"; }

# run SERIES KEY SCENE L N M: one dry run (light-field statistics) and up to $repeat runs.
run() {
  local series=$1 key=$2 scene=$3 l=$4 n=$5 m=$6 i t runs=0
  local opts=(-l "$l" -N "$n" -m "$m" -c 4 -t "$threads")
  "$prop" "$scene" --dry-run "${opts[@]}" --report "$work/$series-$key-dry.json" > /dev/null
  for i in $(seq 1 "$repeat"); do
    "$prop" "$scene" "${opts[@]}" -q -o "$work/run.vlf" --report "$work/$series-$key-$i.json" > /dev/null
    rm -rf "$work/run.vlf"
    runs=$i
    t=$(total_of "$work/$series-$key-$i.json" | xargs printf '%.2f')
    log "$series $key ($scene -l $l -N $n -m $m): run $i/$repeat ${t} s (load $(cut -d' ' -f1 /proc/loadavg))"
    if python3 -c 'import sys; sys.exit(0 if float(sys.argv[1]) > float(sys.argv[2]) else 1)' "$t" "$long_s"; then
      break
    fi
  done
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$series" "$key" "$scene" "$l" "$n" "$m" "$runs" \
    "$(cut -d' ' -f1 /proc/loadavg)" >> "$work/configs.tsv"
}

if [ $quick = 1 ]; then
  dirs="9 33 129 513"; tile_l=129; faces="224 530 836"; fig12=(513 64 8)
else
  dirs="9 33 129 513 2049 8193"; tile_l=513; faces="224 530 836 1124 1430 1736"; fig12=(2049 128 16)
fi
log "start ($([ $quick = 1 ] && echo quick || echo full) run, $prop, threads $threads, load $load_start)"

# Scene summaries (face counts) for the scenes table.
for s in scenes/*.json scenes/complexity/*.json; do
  "$prop" "$s" --dry-run -l 9 -N 8 -m 8 --report "$work/scene-$(echo "$s" | tr '/' '_')" > /dev/null
done
for f in $faces; do
  [ -f "scenes/complexity/complexity-$f.json" ] ||
    { echo "$0: scenes/complexity/complexity-$f.json missing (run bench/make_complexity_scene.py)" >&2; exit 2; }
done

for l in $dirs; do run directions "l$l" scenes/office.json "$l" 64 8; done
for m in 64 32 16 8 4 2; do run tiles "m$m" scenes/office.json "$tile_l" 64 "$m"; done
for f in $faces; do run polygons "f$f" "scenes/complexity/complexity-$f.json" 513 64 8; done
run fig12 main scenes/cornell-mirrors.json "${fig12[@]}"

elapsed=$(($(date +%s) - start))
log "runs done in ${elapsed} s; writing tables and plots"
mkdir -p docs/bench
QUICK=$quick WORK=$work ELAPSED=$elapsed LOAD_START="$load_start" LOAD_END="$(cut -d' ' -f1-3 /proc/loadavg)" \
THREADS=$threads REPEAT=$repeat LONG_S=$long_s BUILD=$build \
COMMIT="$(git describe --always --dirty 2> /dev/null || echo unknown)" \
python3 - << 'PY'
import glob, json, math, os, re, statistics, subprocess, time

W = os.environ["WORK"]
quick = os.environ["QUICK"] == "1"
threads = int(os.environ["THREADS"])
MiB = 2 ** 20

# ---- the paper's figures (§7.1, §7.2): minutes on one 1.7 GHz Xeon core, MB -------------
P_DIR = {129: (8.5, 11), 513: (34, 45), 8193: (489, 733)}
P_TILE_TIME = {64: 111, 16: 61, 2: 150}            # by m (1x1, 4x4, 32x32 tiles)
P_TILE_MEM = {64: 937, 2: 42}
P_TILE_POLY = {64: (121, 10), 2: (1.7, 2.1)}
P_POLY_MEM = {224: 75, 1736: 458}
P_FIG12_MIN = 16 * 60

configs = []
for line in open(f"{W}/configs.tsv"):
    series, key, scene, l, n, m, runs, load = line.rstrip("\n").split("\t")
    reps = [json.load(open(f"{W}/{series}-{key}-{i}.json")) for i in range(1, int(runs) + 1)]
    dry = json.load(open(f"{W}/{series}-{key}-dry.json"))
    totals = [r["timings_s"]["total"] for r in reps]
    configs.append(dict(
        series=series, key=key, scene=scene, l=int(l), N=int(n), m=int(m), runs=int(runs), load=float(load),
        totals=totals, t=statistics.median(totals),
        write=statistics.median(r["timings_s"]["write"] for r in reps),
        rss=statistics.median(r["memory_bytes"]["peak_rss"] for r in reps) / MiB,
        transport=statistics.median(r["memory_bytes"]["transport_total"] for r in reps) / MiB,
        vlf=dry["field"]["memory_bytes"]["total"] / MiB,
        fpt=dry["field"]["fragments_per_tile_mean"], fpt_sd=dry["field"]["fragments_per_tile_stddev"],
        faces=dry["scene"]["faces"], specular=dry["scene"]["specular_faces"],
        ledger=max(e["relative_error"] for r in reps for e in r["ledger"])))
by = lambda s: [c for c in configs if c["series"] == s]


def f(x, d=1):
    return "—" if x is None else f"{x:,.{d}f}"


def secs(x):
    return f"{x:.2f}" if x < 10 else f"{x:.1f}" if x < 100 else f"{x:.0f}"


REPEAT = int(os.environ["REPEAT"])


def runs(c):
    return f"{c['runs']}" + ("" if c["runs"] >= REPEAT else " ¹")


def slope(xs, ys):  # least-squares slope of log y on log x
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = sum(lx) / len(lx), sum(ly) / len(ly)
    den = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / den if den else float("nan")


def linfit(xs, ys):
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    b = sum((a - mx) * (c - my) for a, c in zip(xs, ys)) / sum((a - mx) ** 2 for a in xs)
    return my - b * mx, b


out = []
w = out.append
w(f"Generated by `bench/paper_tables.sh{' --quick' if quick else ''}` on "
  f"{time.strftime('%Y-%m-%d %H:%M %Z')} (build of `{os.environ['COMMIT']}`), "
  f"in {int(os.environ['ELAPSED']) // 60} min {int(os.environ['ELAPSED']) % 60} s.")
w("")
if quick:
    w("**Quick run** (`--quick`): directions up to l = 513, the tile series at l = 129 (the paper: 513), "
      "the three smallest complexity scenes, the Fig. 12 room at l = 513, N = 64, m = 8 (the paper: "
      "2049, 128, 16). Ratios are given only where our configuration is the paper's. "
      "The full series is `bench/paper_tables.sh` (no option).")
    w("")
w(f"Machine: 2 cores (AMD EPYC, virtualised), **shared** with other engineers' builds and tests — "
  f"load average {os.environ['LOAD_START'].split()[0]} at the start, {os.environ['LOAD_END'].split()[0]} at the end "
  f"(per configuration in the `load` column). `propagate -t {threads}` "
  f"({'both cores' if threads == 0 else f'{threads} thread(s)'}); the paper used one 1.7 GHz Xeon core. "
  "Time is wall-clock `timings_s.total` of the `--report` (includes writing the bake, column `write`); "
  f"every figure is the median of {os.environ['REPEAT']} runs unless marked ¹ (a first run over "
  f"{os.environ['LONG_S']} s is not repeated: 1 run). "
  "**speed-up** = paper time / our time (wall against wall, not per core); "
  "**RSS/paper** = our peak resident memory / the paper's memory figure. "
  "`VLF est.` is the light-field estimate of `--dry-run` (tiles, fragments, edge tables, maps — "
  "the structure the paper's memory figure counts); `transport` is what the transport counts "
  "(texture and radiance maps plus the per-direction geometry cache, reserved, not all resident); "
  "peak RSS is the whole process. Fragments per tile are the `--dry-run` statistics "
  "(`field.fragments_per_tile_mean` ± `_stddev`, non-empty tiles), the analogue of the paper's "
  "'polygons per tile'. Worst ledger balance error over all runs: "
  f"{max(c['ledger'] for c in configs):.1e}.")
w("")

# ---- scenes ------------------------------------------------------------------------------
w("#### Scenes")
w("")
w("| scene | faces | emitters | specular faces | used for |")
w("| --- | ---: | ---: | ---: | --- |")
uses = {"scenes/office.json": "directions and tile series (paper Figs. 7, 10, 11: 137 polygons)",
        "scenes/cornell-mirrors.json": "Fig. 12 room", "scenes/ring.json": "ring caustic (Fig. 14: 50 polygons)",
        "scenes/caustic.json": "caustic test (Fig. 13)", "scenes/cornell.json": "—",
        "scenes/closed-box.json": "—"}
for p in sorted(glob.glob(f"{W}/scene-*")):
    s = json.load(open(p))["scene"]
    name = s["source"]
    use = uses.get(name, "polygon series (Figs. 8, 9)" if "complexity" in name else "—")
    w(f"| `{name}` | {s['faces']} | {s['emitters']} | {s['specular_faces']} | {use} |")
w("")


def table_head(first, extra_head="", extra_align=""):
    w(f"| {first} | runs | ours (s) | write (s) | paper (min) | speed-up | peak RSS (MiB) | transport (MiB) "
      f"| VLF est. (MiB) | paper (MB) | RSS/paper | fragments/tile{extra_head} | load |")
    w(f"| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---:{extra_align} | ---: |")


def row(first, c, pmin, pmb, extra=""):
    sp = f"{pmin * 60 / c['t']:,.0f}×" if pmin else "—"
    rr = f"{c['rss'] / pmb:.2f}" if pmb else "—"
    w(f"| {first} | {runs(c)} | **{secs(c['t'])}** | {secs(c['write'])} | {f(pmin)} | {sp} | {f(c['rss'])} "
      f"| {f(c['transport'])} | {f(c['vlf'])} | {f(pmb, 0)} | {rr} | {c['fpt']:.2f} ± {c['fpt_sd']:.2f}{extra} "
      f"| {c['load']:.1f} |")


# ---- directions --------------------------------------------------------------------------
D = by("directions")
w("#### PSF directions (paper §7.1 'PSF Directions': office scene, N = 64, m = 8, 4 cycles)")
w("")
w("Command: `build/propagate/propagate scenes/office.json -o OUT.vlf -l L -N 64 -m 8 -c 4 "
  f"-t {threads} --report R.json -q`")
w("")
table_head("l")
for c in D:
    pm, pb = P_DIR.get(c["l"], (None, None))
    row(str(c["l"]), c, pm, pb)
w("")
big = [c for c in D if c["l"] >= 129]
if len(big) >= 2:
    w(f"Growth with l from l = 129 on (log-log slope; 1 = linear): ours time "
      f"{slope([c['l'] for c in big], [c['t'] for c in big]):.2f}, peak RSS "
      f"{slope([c['l'] for c in big], [c['rss'] for c in big]):.2f}, VLF est. "
      f"{slope([c['l'] for c in big], [c['vlf'] for c in big]):.2f}; paper time "
      f"{slope([129, 513, 8193], [8.5, 34, 489]):.2f}, memory {slope([129, 513, 8193], [11, 45, 733]):.2f} "
      "(129 → 8193).")
    w("")
w("![time and memory against the number of directions](docs/bench/paper-directions.png)")
w("")

# ---- tiles -------------------------------------------------------------------------------
T = by("tiles")
tl = T[0]["l"] if T else 513
w(f"#### Tiles (paper Fig. 10: office scene, N = 64, n × n tiles = m = 64 … 2, l = {tl}"
  f"{' — the paper: 513' if tl != 513 else ''}, 4 cycles)")
w("")
w(f"Command: `build/propagate/propagate scenes/office.json -o OUT.vlf -l {tl} -N 64 -m M -c 4 "
  f"-t {threads} --report R.json -q` and the same with `--dry-run` for the fragments per tile.")
w("")
table_head("tiles (m)", " | paper polygons/tile", " | ---:")
for c in T:
    n = c["N"] // c["m"]
    like = c["l"] == 513
    pp = P_TILE_POLY.get(c["m"])
    row(f"{n}×{n} ({c['m']})", c, P_TILE_TIME.get(c["m"]) if like else None, P_TILE_MEM.get(c["m"]) if like else None,
        f" | {f'{pp[0]} ± {pp[1]}' if pp else '—'}")
if T:
    best = min(T, key=lambda c: c["t"])
    w("")
    w(f"Fastest tiling: {best['N'] // best['m']}×{best['N'] // best['m']} (m = {best['m']}) at {secs(best['t'])} s "
      "(the paper: 4×4 at 61 min, 1×1 111 min, 32×32 150 min). "
      + ("The paper's times and memory are at l = 513, so no ratios here." if tl != 513 else ""))
w("")
w("![normalised memory, time and fragments per tile against the tiling](docs/bench/paper-tiles.png)")
w("")

# ---- polygons ----------------------------------------------------------------------------
Pn = by("polygons")
w("#### Number of polygons (paper Figs. 8, 9: complexity scenes, one emitter, diffuse : specular = 5 : 1, "
  "l = 513, N = 64, m = 8, 4 cycles)")
w("")
w("Scenes: `bench/make_complexity_scene.py` → `scenes/complexity/complexity-<faces>.json`: a closed 6 m room, "
  "a ceiling lamp, a wall mirror and k floating cubes (every sixth a mirror) on an n × n × n lattice, "
  "n = ⌈k^(1/3)⌉, cube edge half the lattice pitch — the room is fixed, so the cubes shrink as they multiply "
  "and the total area grows only about as k^(1/3) while the fragments per tile grow. Command: "
  "`build/propagate/propagate scenes/complexity/complexity-<faces>.json -o OUT.vlf -l 513 -N 64 -m 8 -c 4 "
  f"-t {threads} --report R.json -q`")
w("")
table_head("faces (specular)")
for c in Pn:
    row(f"{c['faces']} ({c['specular']})", c, None, P_POLY_MEM.get(c["faces"]))
if len(Pn) >= 2:
    fx = [c["faces"] for c in Pn]
    a, b = linfit(fx, [c["rss"] for c in Pn])
    w("")
    w(f"Growth with the number of faces (log-log slope; paper: time quadratic = 2, memory linear): ours time "
      f"{slope(fx, [c['t'] for c in Pn]):.2f}, time minus write {slope(fx, [c['t'] - c['write'] for c in Pn]):.2f}, "
      f"peak RSS {slope(fx, [c['rss'] for c in Pn]):.2f} (linear fit {a:.0f} MiB + {b:.3f} MiB/face), VLF est. "
      f"{slope(fx, [c['vlf'] for c in Pn]):.2f}, fragments per tile {slope(fx, [c['fpt'] for c in Pn]):.2f}. "
      "The paper gives memory 75 MB (224 faces) → 458 MB (1736) and its times only as a plot (Fig. 9).")
w("")
w("![time and memory against the number of polygons](docs/bench/paper-polygons.png)")
w("")

# ---- Fig. 12 -----------------------------------------------------------------------------
F = by("fig12")
w("#### The Fig. 12 room (paper §7.2: Cornell room with mirrors, N = 128, m = 16, l = 2049: 16 h)")
w("")
for c in F:
    w(f"Command: `build/propagate/propagate scenes/cornell-mirrors.json -o OUT.vlf -l {c['l']} -N {c['N']} "
      f"-m {c['m']} -c 4 -t {threads} --report R.json -q`")
    w("")
    w("| configuration | runs | ours (s) | write (s) | paper | speed-up | peak RSS (MiB) | VLF est. (MiB) | "
      "fragments/tile | load |")
    w("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    like = (c["l"], c["N"], c["m"]) == (2049, 128, 16)
    sp = f"{P_FIG12_MIN * 60 / c['t']:,.0f}×" if like else "—"
    w(f"| {c['faces']} faces, l = {c['l']}, N = {c['N']}, m = {c['m']} | {runs(c)} | **{secs(c['t'])}** "
      f"| {secs(c['write'])} | {'16 h' if like else '16 h (at 2049/128/16)'} "
      f"| {sp} | {f(c['rss'])} | {f(c['vlf'])} "
      f"| {c['fpt']:.2f} ± {c['fpt_sd']:.2f} | {c['load']:.1f} |")
w("")
if any(c["runs"] < REPEAT for c in configs):
    w("")
    w("¹ fewer runs than " + str(REPEAT) + ": its first run took over " + os.environ["LONG_S"] + " s.")

# ---- plots -------------------------------------------------------------------------------
term = "pngcairo size 1000,420 font 'Sans,10'"
if subprocess.run(["gnuplot", "-e", "set terminal pngcairo"], capture_output=True).returncode != 0:
    term = "png size 1000,420"
tag = " (quick run)" if quick else ""


def dat(name, rows):
    with open(f"{W}/{name}.dat", "w") as fh:
        for r in rows:
            fh.write(" ".join(str(x) for x in r) + "\n")
    return f"{W}/{name}.dat"


gp = []
d1 = dat("dir", [(c["l"], c["t"], c["rss"], c["vlf"]) for c in D])
d2 = dat("dirp", [(l, t, m) for l, (t, m) in sorted(P_DIR.items())])
gp.append(f"""set terminal {term}
set output 'docs/bench/paper-directions.png'
set multiplot layout 1,2 title 'PSF directions, office scene (137 faces), N = 64, m = 8, 4 cycles{tag}'
set logscale xy; set grid; set key top left; set xlabel 'directions l'
set ylabel 'ours: wall s'; set y2label 'paper: min (1 core, 1.7 GHz)'; set logscale y2; set y2tics; set ytics nomirror
set title 'propagation time'
plot '{d1}' u 1:2 w lp pt 7 t 'ours (s)', '{d2}' u 1:2 axes x1y2 w lp pt 5 dt 2 t 'paper (min, right axis)'
unset y2label; unset y2tics; set ytics mirror; set ylabel 'MiB / MB'
set title 'memory'
plot '{d1}' u 1:3 w lp pt 7 t 'ours peak RSS (MiB)', '{d1}' u 1:4 w lp pt 6 t 'ours VLF est. (MiB)', '{d2}' u 1:3 w lp pt 5 dt 2 t 'paper (MB)'
unset multiplot
""")
if T:
    mt, mr, mf = max(c["t"] for c in T), max(c["rss"] for c in T), max(c["fpt"] for c in T)
    mv = max(c["vlf"] for c in T)
    d3 = dat("tiles", [(c["N"] // c["m"], c["t"] / mt, c["rss"] / mr, c["vlf"] / mv, c["fpt"] / mf) for c in T])
    d4 = dat("tilesp", [(64 // m, P_TILE_TIME[m] / 150, P_TILE_MEM[m] / 937 if m in P_TILE_MEM else "NaN",
                         P_TILE_POLY[m][0] / 121 if m in P_TILE_POLY else "NaN") for m in (64, 16, 2)])
    gp.append(f"""set terminal {term}
set output 'docs/bench/paper-tiles.png'
set title 'Tiling of a 64x64 PSF, office scene, l = {tl}, 4 cycles, normalised to each series maximum{tag}'
set logscale x 2; set grid; set key outside right; set xlabel 'tiles per PSF side n (n x n tiles, m = 64/n)'
set ylabel 'normalised (0-1)'; set yrange [0:1.05]; set xtics ('1' 1, '2' 2, '4' 4, '8' 8, '16' 16, '32' 32)
plot '{d3}' u 1:2 w lp pt 7 lc 1 t 'ours time', '{d3}' u 1:3 w lp pt 7 lc 2 t 'ours peak RSS', \\
     '{d3}' u 1:4 w lp pt 6 lc 2 dt 3 t 'ours VLF est.', '{d3}' u 1:5 w lp pt 7 lc 3 t 'ours fragments/tile', \\
     '{d4}' u 1:2 w p pt 5 ps 1.5 lc 1 t 'paper time', '{d4}' u 1:3 w p pt 5 ps 1.5 lc 2 t 'paper memory', \\
     '{d4}' u 1:4 w p pt 5 ps 1.5 lc 3 t 'paper polygons/tile'
""")
if Pn:
    d5 = dat("poly", [(c["faces"], c["t"], c["rss"], c["vlf"], c["t"] - c["write"]) for c in Pn])
    d6 = dat("polyp", sorted(P_POLY_MEM.items()))
    gp.append(f"""set terminal {term}
set output 'docs/bench/paper-polygons.png'
set multiplot layout 1,2 title 'Complexity scenes (1 emitter, diffuse:specular 5:1), l = 513, N = 64, m = 8, 4 cycles{tag}'
set grid; set key bottom right; set xlabel 'faces'; set xrange [0:1900]
set title 'propagation time (paper: quadratic)'; set ylabel 'wall s'; set yrange [0:*]
plot '{d5}' u 1:2 w lp pt 7 t 'ours total', '{d5}' u 1:5 w lp pt 6 t 'ours without writing the bake'
set title 'memory (paper: linear, 75 -> 458 MB)'; set ylabel 'MiB / MB'
plot '{d5}' u 1:3 w lp pt 7 t 'ours peak RSS (MiB)', '{d5}' u 1:4 w lp pt 6 t 'ours VLF est. (MiB)', '{d6}' u 1:2 w lp pt 5 dt 2 t 'paper (MB)'
unset multiplot
""")
for i, g in enumerate(gp):
    with open(f"{W}/plot{i}.gp", "w") as fh:
        fh.write(g)
    r = subprocess.run(["gnuplot", f"{W}/plot{i}.gp"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"gnuplot failed: {r.stderr}")

# ---- splice into BENCHMARKS.md -----------------------------------------------------------
md = open("BENCHMARKS.md").read()
b, e = "<!-- paper-tables:begin -->", "<!-- paper-tables:end -->"
i, j = md.index(b) + len(b), md.index(e)
open("BENCHMARKS.md", "w").write(md[:i] + "\n" + "\n".join(out) + "\n" + md[j:])
PY
log "wrote BENCHMARKS.md (between the paper-tables markers) and docs/bench/paper-{directions,tiles,polygons}.png"
log "done in $(($(date +%s) - start)) s"

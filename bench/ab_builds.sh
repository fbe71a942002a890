#!/usr/bin/env bash
# Two builds of Irradia side by side on the benchmarks of docs/benchmarks.md: each
# workload runs A B A B ... (RUNS pairs, interleaved so that drift in the machine's speed
# hits both alike), timed as whole processes; prints per workload the median wall time of
# each build and the median of the per-pair ratios B / A.
#
# Usage: bench/ab_builds.sh OLD_TARGET NEW_TARGET [RUNS]
#   OLD_TARGET, NEW_TARGET: cargo target folders holding release builds of
#   `irradia` and the examples `raster_bench`, `triangles_bench`, `radiosity_bench`
#   (cargo build --release -p irradia -p irradia-raster --example raster_bench
#    -p irradia-geometry --example triangles_bench -p irradia-radiosity --example radiosity_bench).
# The gyroid and random-triangle inputs are written once by the NEW build's examples
# into $AB_DATA (default /tmp/irradia-ab).
set -euo pipefail
old=$1 new=$2 runs=${3:-5}
data=${AB_DATA:-/tmp/irradia-ab}
mkdir -p "$data"
[ -f "$data/tri/incoherent_dir.f32" ] || "$new/release/examples/triangles_bench" write "$data/tri" >/dev/null
for w in random gyroid; do
  [ -f "$data/$w.bin" ] || "$new/release/examples/raster_bench" write "$w" "$data/$w.bin" >/dev/null
done

# name|command with @T@ for the target folder
workloads=(
  "whitted 1 thread|@T@/release/irradia render --builtin whitted --threads 1 --quiet -o $data/w.png"
  "whitted 2 threads|@T@/release/irradia render --builtin whitted --threads 2 --quiet -o $data/w.png"
  "csg 1 thread|@T@/release/irradia render --builtin csg --threads 1 --quiet -o $data/c.png"
  "csg 2 threads|@T@/release/irradia render --builtin csg --threads 2 --quiet -o $data/c.png"
  "path cornell 512x512x64 2 threads|@T@/release/irradia render --builtin cornell --threads 2 --quiet -o $data/p.png"
  "triangles (build, primary, incoherent) 2 threads|env RAYON_NUM_THREADS=2 @T@/release/examples/triangles_bench run $data/tri"
  "raster 1M random triangles 2 threads|@T@/release/examples/raster_bench time $data/random.bin 5 2"
  "raster gyroid 2 threads|@T@/release/examples/raster_bench time $data/gyroid.bin 5 2"
  "radiosity 100k hierarchical 2 threads|env RAYON_NUM_THREADS=2 @T@/release/examples/radiosity_bench 100000 hemicube hierarchical 1e-4"
)

wall() { local s e; s=$(date +%s.%N); "$@" >/dev/null 2>&1; e=$(date +%s.%N); echo "$e - $s" | bc -l; }
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }

echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(nproc) cores  load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| workload | old (s) | new (s) | new / old (median of pairs) |"
echo "|---|---|---|---|"
for w in "${workloads[@]}"; do
  name=${w%%|*} cmd=${w#*|}
  a=() b=() r=()
  read -r -a ca <<<"${cmd//@T@/$old}"
  read -r -a cb <<<"${cmd//@T@/$new}"
  "${ca[@]}" >/dev/null 2>&1; "${cb[@]}" >/dev/null 2>&1   # warm-up
  for ((i = 0; i < runs; i++)); do
    ta=$(wall "${ca[@]}"); tb=$(wall "${cb[@]}")
    a+=("$ta") b+=("$tb") r+=("$(echo "$tb / $ta" | bc -l)")
  done
  printf '| %s | %.3f | %.3f | %.3f |\n' "$name" \
    "$(printf '%s\n' "${a[@]}" | median)" "$(printf '%s\n' "${b[@]}" | median)" \
    "$(printf '%s\n' "${r[@]}" | median)"
done

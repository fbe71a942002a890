#!/usr/bin/env bash
# Radiosity benchmark: the measured Cornell box with blocks, hierarchical radiosity
# (form factors with occlusion + solution) at 10,000 and 100,000 elements, with 1 and 2
# threads, 5 interleaved runs each (10k 100k 10k 100k ...); prints medians, the
# 100k/10k ratio and where the time goes. Results go in docs/benchmarks/radiosity.md.
#
# Usage: bench/radiosity/run.sh [RUNS]   (from the repository root)
set -euo pipefail
RUNS=${1:-5}
cd "$(dirname "$0")/../.."
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target}
cargo build --release -q -p irradia-radiosity --example radiosity_bench
BIN="$CARGO_TARGET_DIR/release/examples/radiosity_bench"
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(nproc) cores, $(free -g | awk '/Mem/{print $2}') GiB"
echo "load: $(uptime)"
declare -A T
for threads in 1 2; do
  for ((i = 0; i < RUNS; i++)); do
    for n in 10000 100000; do
      line=$(RAYON_NUM_THREADS=$threads "$BIN" "$n" hemicube hierarchical)
      t=$(sed -E 's/.*total_s=([0-9.]+).*/\1/' <<<"$line")
      T[$threads,$n]+="$t "
      echo "threads=$threads n=$n run=$i: $line" >&2
    done
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
echo
echo "| threads | 10k elements (s) | 100k elements (s) | 100k / 10k |"
echo "|---|---|---|---|"
for threads in 1 2; do
  a=$(echo "${T[$threads,10000]}" | median)
  b=$(echo "${T[$threads,100000]}" | median)
  echo "| $threads | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN{printf "%.2f", b/a}') |"
done
echo
echo "Where the time goes (last 2-thread runs):"
RAYON_NUM_THREADS=2 "$BIN" 10000 hemicube hierarchical | tr ' ' '\n' | grep -E '^\[|^elements|^total|^display|^note'
RAYON_NUM_THREADS=2 "$BIN" 100000 hemicube hierarchical | tr ' ' '\n' | grep -E '^\[|^elements|^total|^display|^note'

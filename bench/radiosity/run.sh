#!/usr/bin/env bash
# Radiosity benchmark: the measured Cornell box with blocks, hierarchical radiosity
# (form factors with occlusion + solution) at 10,000 and 100,000 elements, with 1 and 2
# threads, 5 interleaved runs each (10k 100k 10k 100k ...); prints medians, the
# 100k/10k ratio and where the time goes. Results go in docs/benchmarks/radiosity.md.
#
# Usage: bench/radiosity/run.sh [RUNS] [PROFILE]   (from the repository root)
# The hierarchical solver picks the leaf area that gives the target number of leaves
# (a grid of cells per patch, quadtrees below), so 10000 and 100000 give within 2% of
# that many leaves; ε_BF = 1e-4.
set -euo pipefail
RUNS=${1:-5}
PROFILE=${2:-release}
cd "$(dirname "$0")/../.."
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target}
cargo build --profile "$PROFILE" -q -p irradia-radiosity --example radiosity_bench
DIR=$PROFILE; [ "$PROFILE" = test ] && DIR=debug
BIN="$CARGO_TARGET_DIR/$DIR/examples/radiosity_bench"
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(nproc) cores, $(free -g | awk '/Mem/{print $2}') GiB"
echo "load: $(uptime)"
declare -A T
for threads in 1 2; do
  for ((i = 0; i < RUNS; i++)); do
    for n in 10000 100000; do
      line=$(RAYON_NUM_THREADS=$threads "$BIN" "$n" hemicube hierarchical 1e-4)
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

for n in 10000 100000; do
  RAYON_NUM_THREADS=2 "$BIN" "$n" hemicube hierarchical 1e-4 | sed -E 's/ \[/\n  [/g; s/ note=/\n  note=/g'
done

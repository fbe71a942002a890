#!/usr/bin/env bash
# Radiosity benchmark: the measured Cornell box with blocks, hierarchical radiosity
# (form factors with occlusion + solution) at 10,000, 100,000 and 1,000,000 elements,
# with 1 and 2 threads, RUNS interleaved runs each (10k 100k 1M 10k 100k 1M ...);
# prints medians of the solve time (wall), of the CPU seconds up to the end of the
# solve (user + system, all threads: what a loaded machine does not inflate) and of
# the peak memory (/usr/bin/time %M), the
# 100k/10k and 1M/100k ratios and where the time goes. Results go in
# docs/benchmarks/radiosity.md and docs/benchmarks.md (issue 14 goal 5: 1M in at most
# 15 s on 2 threads, time growing at most linearly from 100k).
#
# Usage: bench/radiosity/run.sh [RUNS] [PROFILE]   (from the repository root)
#        SIZES="10000 100000" THREADS="2" bench/radiosity/run.sh 3
# The hierarchical solver picks the leaf area that gives the target number of leaves
# (a grid of cells per patch, quadtrees below), so each size gives within 2% of that
# many leaves (1,000,000: 993,216); ε_BF = 1e-4.
set -euo pipefail
RUNS=${1:-5}
PROFILE=${2:-release}
SIZES=${SIZES:-"10000 100000 1000000"}
THREADS=${THREADS:-"1 2"}
cd "$(dirname "$0")/../.."
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target}
cargo build --profile "$PROFILE" -q -p irradia-radiosity --example radiosity_bench
DIR=$PROFILE; [ "$PROFILE" = test ] && DIR=debug
BIN="$CARGO_TARGET_DIR/$DIR/examples/radiosity_bench"
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(nproc) cores, $(free -g | awk '/Mem/{print $2}') GiB"
echo "load: $(uptime)"
declare -A T M C
LAST=$(mktemp)
trap 'rm -f "$LAST" "$LAST.mem"' EXIT
for threads in $THREADS; do
  for ((i = 0; i < RUNS; i++)); do
    for n in $SIZES; do
      RAYON_NUM_THREADS=$threads /usr/bin/time -f "%M" -o "$LAST.mem" \
        "$BIN" "$n" hemicube hierarchical 1e-4 >"$LAST"
      line=$(cat "$LAST")
      t=$(sed -E 's/.*total_s=([0-9.]+).*/\1/' <<<"$line")
      T[$threads,$n]+="$t "
      C[$threads,$n]+="$(sed -nE 's/.*cpu_to_solve_end_s=([0-9.]+).*/\1/p' <<<"$line") "
      M[$threads,$n]+="$(cat "$LAST.mem") "
      echo "threads=$threads n=$n run=$i: $line peak_kib=$(cat "$LAST.mem")" >&2
    done
  done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
echo
printf "| threads |"; for n in $SIZES; do printf " %s elements: s (CPU s; peak MiB) |" "$n"; done
echo " ratios (time, each size / the one before) |"
printf "|---|"; for n in $SIZES; do printf -- "---|"; done; echo "---|"
for threads in $THREADS; do
  printf "| %s |" "$threads"
  prev=""; ratios=""
  for n in $SIZES; do
    a=$(echo "${T[$threads,$n]}" | median)
    m=$(echo "${M[$threads,$n]}" | median)
    c=$(echo "${C[$threads,$n]}" | median)
    printf " %s (%s; %s) |" "$a" "$c" "$(awk -v m="$m" 'BEGIN{printf "%.0f", m/1024}')"
    [ -n "$prev" ] && ratios+="$(awk -v a="$prev" -v b="$a" 'BEGIN{printf "%.2f", b/a}') "
    prev=$a
  done
  echo " $ratios|"
done
echo
echo "Where the time goes (one more 2-thread run each):"
for n in $SIZES; do
  RAYON_NUM_THREADS=2 "$BIN" "$n" hemicube hierarchical 1e-4 | sed -E 's/ \[/\n  [/g; s/ note=/\n  note=/g'
done

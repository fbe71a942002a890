#!/usr/bin/env bash
# Binary swap of 1280x720 RGBA8 + f32 depth over MPI: Irradia against mpi4py + numpy,
# interleaved A B A B (ROUNDS times, default 5) at 2 and 4 ranks, in one run. The Irradia
# binary also measures the transfer bound in the same run with the same ranks: per
# binary-swap round, a concurrent pairwise exchange (every rank with its round partner)
# of that round's message size; bound = sum over rounds of those exchange times
# (docs/benchmarks/composite.md says exactly how). REPS repetitions per launch (default 21).
# The same launches time direct send and radix-k (k = 4) on the same images, and the
# 10%-active image both found by scanning and given as the renderer's rectangle.
#   bash bench/composite/run.sh            # prints a summary; raw lines in $OUT (default /tmp/composite-bench.txt)
set -euo pipefail
cd "$(dirname "$0")/../.."
ROUNDS=${ROUNDS:-5}
REPS=${REPS:-21}
OUT=${OUT:-/tmp/composite-bench.txt}
command -v mpirun >/dev/null || { echo "composite bench: mpirun not found (apt-get install openmpi-bin libopenmpi-dev libclang-dev); skipping"; exit 0; }
python3 -c "import mpi4py" 2>/dev/null || python3 -m pip install mpi4py || { echo "composite bench: mpi4py unavailable; skipping the baseline"; }
cargo build --release --locked -p irradia-parallel --features mpi --example composite_bench
BIN="${CARGO_TARGET_DIR:-target}/release/examples/composite_bench"
MPIRUN=(mpirun --oversubscribe --bind-to none)
if [ "$(id -u)" = 0 ]; then MPIRUN+=(--allow-run-as-root); fi
: > "$OUT"
echo "load: $(uptime)" | tee -a "$OUT"
for round in $(seq 1 "$ROUNDS"); do
  for np in 2 4; do
    "${MPIRUN[@]}" -np "$np" "$BIN" --reps "$REPS" | grep -E "RESULT|PROFILE" | sed "s/^/round=$round /" >> "$OUT"
    if python3 -c "import mpi4py" 2>/dev/null; then
      "${MPIRUN[@]}" -np "$np" python3 bench/composite/binary_swap_mpi4py.py --reps "$REPS" | grep RESULT | sed "s/^/round=$round /" >> "$OUT"
    fi
  done
done
echo "load: $(uptime)" | tee -a "$OUT"
python3 - "$OUT" <<'PY'
import re, statistics, sys
rows = []
for line in open(sys.argv[1]):
    if "RESULT" not in line:
        continue
    rows.append(dict(re.findall(r"(\w+)=([\w.-]+)", line)))
def med(np_, key, case=None, strategy=None):
    v = [float(r[key]) for r in rows if r.get("np") == np_ and key in r
         and (case is None or r.get("case") == case)
         and (strategy is None or r.get("strategy") == strategy)]
    return statistics.median(v) if v else float("nan")
bs = "binary-swap"
print("\nbinary swap (10%-active: one centred blob; 'scan' finds it in the depth plane, 'rect' is given the renderer's rectangle)")
print("np | irradia dense ms | mpi4py ms | ratio | round GB/s | bound ms | dense/bound | 10% scan ms | dense/10% scan | 10% rect ms | dense/10% rect | best-of: dense/bound, dense/10% scan, dense/10% rect")
for np_ in ["2", "4"]:
    d, b = med(np_, "median_ms", "dense", bs), med(np_, "median_ms", "mpi4py")
    bound = med(np_, "bound_ms")
    gbps = [r for r in rows if r.get("np") == np_ and "exchange_gbps" in r]
    s, sr = med(np_, "median_ms", "active10", bs), med(np_, "median_ms", "active10rect", bs)
    dmin, bmin = med(np_, "min_ms", "dense", bs), med(np_, "bound_min_ms")
    smin, srmin = med(np_, "min_ms", "active10", bs), med(np_, "min_ms", "active10rect", bs)
    g = "/".join(f"{statistics.median(float(r['exchange_gbps']) for r in gbps if r['swap_round'] == k):.1f}" for k in sorted({r['swap_round'] for r in gbps}))
    print(f"{np_} | {d:.2f} | {b:.2f} | {d/b:.2f} | {g} | {bound:.2f} | {d/bound:.2f} | {s:.2f} | {d/s:.1f} | {sr:.2f} | {d/sr:.1f} | {dmin/bmin:.2f}, {dmin/smin:.1f}, {dmin/srmin:.1f}")
print("\nother strategies on the same images (medians; best-of in brackets); radix-4 at 4 ranks is one round of 4, i.e. direct send")
print("np | strategy | dense ms | dense/bound | 10% scan ms | dense/10%")
for np_ in ["2", "4"]:
    bound, bmin = med(np_, "bound_ms"), med(np_, "bound_min_ms")
    for st in ["direct-send", "radix-4"]:
        d, s = med(np_, "median_ms", "dense", st), med(np_, "median_ms", "active10", st)
        dmin, smin = med(np_, "min_ms", "dense", st), med(np_, "min_ms", "active10", st)
        print(f"{np_} | {st} | {d:.2f} [{dmin:.2f}] | {d/bound:.2f} [{dmin/bmin:.2f}] | {s:.2f} [{smin:.2f}] | {d/s:.1f} [{dmin/smin:.1f}]")
print("\ntargets: ratio <= 0.5, dense/bound <= 2, dense/10% >= 4 (medians over launches of each launch's median;")
print("best-of columns: medians over launches of each launch's minimum, less sensitive to machine load)")
PY

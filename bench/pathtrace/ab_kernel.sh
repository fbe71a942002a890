#!/usr/bin/env bash
# A/B of the path tracer's two estimator codes on the Cornell box: the 8-wide kernel
# (default) against the scalar one (IRRADIA_PATH_KERNEL=scalar), interleaved, same
# binary. User (CPU) time is reported beside wall time because it moves least with
# the load of other programs on the machine.
#
# Usage: bash bench/pathtrace/ab_kernel.sh [RUNS=5] [THREADS="1 2"] [SPP=16] [RES=512]
set -euo pipefail
RUNS=${1:-5}
THREADS=${2:-"1 2"}
SPP=${3:-16}
RES=${4:-512}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
cd "$ROOT"
cargo build --release -q -p irradia
BIN=${CARGO_TARGET_DIR:-$ROOT/target}/release/irradia
OUT=$(mktemp -d)
echo "cornell ${RES}x${RES}, ${SPP} spp, $(date -u '+%F %H:%M UTC'), load: $(cut -d' ' -f1-3 /proc/loadavg)"
for t in $THREADS; do
  for k in wide scalar; do : >"$OUT/$k.$t"; done
  for _ in $(seq "$RUNS"); do
    for k in wide scalar; do
      env $([ $k = scalar ] && echo IRRADIA_PATH_KERNEL=scalar) /usr/bin/time -f "%e %U" -o "$OUT/t" \
        "$BIN" render --builtin cornell --spp "$SPP" --width "$RES" --height "$RES" \
        --threads "$t" --quiet -o "$OUT/img.pfm"
      cat "$OUT/t" >>"$OUT/$k.$t"
    done
  done
  python3 - "$OUT" "$t" "$RES" "$SPP" <<'EOF'
import statistics, sys
out, t, res, spp = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
m = {}
for k in ("wide", "scalar"):
    rows = [tuple(map(float, l.split())) for l in open(f"{out}/{k}.{t}") if l.strip()]
    wall, user = statistics.median(r[0] for r in rows), statistics.median(r[1] for r in rows)
    m[k] = (wall, user)
    print(f"  {t} thread(s) {k:6s} wall {wall:6.2f} s ({res*res*spp/wall/1e6:5.2f} Msamples/s)"
          f"  user {user:6.2f} s   runs {[r[0] for r in rows]}")
print(f"  {t} thread(s) wide/scalar speed: wall {m['scalar'][0]/m['wide'][0]:.2f}x, "
      f"user {m['scalar'][1]/m['wide'][1]:.2f}x")
EOF
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"

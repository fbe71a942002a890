#!/usr/bin/env bash
# The csg workload (PEERS.md): Irradia's `render --builtin csg` against POV-Ray 3.7 on
# ../shared/peers/csg.pov, whole process, 1280x720, 1 spp, interleaved A B A B, medians
# of N runs (default 5) at 1 and 2 threads; plus the geometry-only ray rate of the CSG
# objects (crates/geometry/examples/csg_rays.rs, 1 thread).
#
#   bench/csg-geometry/run.sh [runs]
#
# Wall times depend on machine load: the script prints `uptime` with the figures, and
# user CPU seconds beside wall seconds.
set -euo pipefail
cd "$(dirname "$0")/../.."
RUNS=${1:-5}
POV_SCENE=${POV_SCENE:-../shared/peers/csg.pov}
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target}
cargo build --release -q -p irradia -p irradia-geometry --example csg_rays
IRRADIA=$CARGO_TARGET_DIR/release/irradia
if ! command -v povray >/dev/null; then
  (apt-get install -y povray >/dev/null 2>&1) || echo "povray not available: skipping the comparison"
fi
OUT=$(mktemp -d)
median() { sort -g | awk '{a[NR]=$1} END {print (NR%2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'; }
timed() { /usr/bin/time -f "%e %U" "$@" 2>&1 >/dev/null | tail -1; }
echo "load before: $(uptime)"
for threads in 1 2; do
  : >"$OUT/irr" ; : >"$OUT/pov"
  for _ in $(seq "$RUNS"); do
    timed "$IRRADIA" render --builtin csg -o "$OUT/irradia.png" --threads "$threads" --quiet >>"$OUT/irr"
    if command -v povray >/dev/null; then
      timed povray +I"$POV_SCENE" +O"$OUT/pov.png" +W1280 +H720 -A +WT"$threads" -D -V >>"$OUT/pov"
    fi
  done
  iw=$(cut -d' ' -f1 "$OUT/irr" | median); iu=$(cut -d' ' -f2 "$OUT/irr" | median)
  if [ -s "$OUT/pov" ]; then
    pw=$(cut -d' ' -f1 "$OUT/pov" | median); pu=$(cut -d' ' -f2 "$OUT/pov" | median)
    echo "threads $threads: irradia wall ${iw}s (user ${iu}s), povray wall ${pw}s (user ${pu}s), wall ratio $(echo "$iw / $pw" | bc -l | cut -c1-5), user ratio $(echo "$iu / $pu" | bc -l | cut -c1-5)"
  else
    echo "threads $threads: irradia wall ${iw}s (user ${iu}s)"
  fi
done
echo "geometry only: $("$CARGO_TARGET_DIR"/release/examples/csg_rays "$RUNS")"
echo "load after: $(uptime)"
rm -rf "$OUT"

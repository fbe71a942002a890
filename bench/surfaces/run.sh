#!/usr/bin/env bash
# Primary-ray throughput of Irradia's curved surfaces (torus, Bézier teapot, implicit
# surfaces with interval and Lipschitz root finding, parametric surface), with 1 and 2
# threads, interleaved (1 2 1 2 ...), each a median over 5 runs. No peer: POV-Ray's
# torus / bicubic_patch / isosurface are not timed separately from its whole render.
# Usage: bench/surfaces/run.sh [ROUNDS]   (default 3 rounds of 1 and 2 threads)
set -euo pipefail
cd "$(dirname "$0")/../.."
rounds=${1:-3}
cargo build --release -p irradia-geometry --example surfaces_throughput >/dev/null 2>&1
bin="${CARGO_TARGET_DIR:-target}/release/examples/surfaces_throughput"
echo "date: $(date -u +%FT%TZ)   load: $(uptime | sed 's/.*load average: //')"
for r in $(seq "$rounds"); do
  for t in 1 2; do
    echo "--- round $r, $t thread(s)"
    "$bin" "$t" 5
  done
done

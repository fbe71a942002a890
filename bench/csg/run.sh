#!/usr/bin/env bash
# The 'csg' workload of PEERS.md: Irradia's built-in `csg` against POV-Ray 3.7 rendering
# csg.pov (copied from /work/shared/peers/), 1280x720, 1 spp, 1 and 2 threads,
# whole-process wall time, interleaved runs; plus the PSNR of the two PNGs.
# Usage: bench/csg/run.sh [RUNS]   (default 7)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
exec "$here/../whitted/bench.sh" csg "$here/csg.pov" "${1:-7}"

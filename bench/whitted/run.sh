#!/usr/bin/env bash
# The 'whitted' workload of PEERS.md: Irradia's built-in `whitted` against POV-Ray 3.7
# rendering /work/shared/peers/whitted.pov (a copy is in this folder), 1280x720, 1 spp,
# 1 and 2 threads, whole-process wall time, interleaved runs; plus the PSNR of the two
# PNGs. Usage: bench/whitted/run.sh [RUNS]   (default 7)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
exec "$here/bench.sh" whitted "$here/whitted.pov" "${1:-7}"

#!/usr/bin/env bash
# Irradia against POV-Ray 3.7 with farm-bench (whole process, interleaved pairs A B A B,
# medians of the pair ratios), the `whitted` and `csg` workloads at 1280x720, 1 and 2
# threads; then the PSNR of the last pair's PNGs. Usage:
#   bench/whitted/farm.sh IRRADIA_BIN [PAIRS]   (default 15)
set -euo pipefail
bin="$1"; n="${2:-15}"
here="$(cd "$(dirname "$0")" && pwd)"
out="$(mktemp -d)"
command -v povray >/dev/null || { apt-get install -y povray >/dev/null 2>&1 || true; }
command -v povray >/dev/null || { echo "SKIP: povray is not available" >&2; exit 0; }
for s in whitted csg; do
  pov="$here/../$s/$s.pov"; [ -f "$pov" ] || pov="$here/$s.pov"
  for t in 1 2; do
    echo "=== $s, $t thread(s), $(date -u +%H:%M:%SZ), load $(cut -d' ' -f1-3 /proc/loadavg)"
    farm-bench -n "$n" --timeout 900 \
      --vs "povray +W1280 +H720 -A +WT$t -D -V -GA +I$pov +O$out/pov_$s.png" -- \
      "$bin" render --builtin "$s" --threads "$t" --width 1280 --height 720 --quiet -o "$out/irr_$s.png"
  done
  python3 -c "
import math, sys, numpy as np; from PIL import Image
a, b = (np.asarray(Image.open(p).convert('RGB'), dtype=float) for p in sys.argv[1:3])
print('PSNR $s: %.1f dB' % (10 * math.log10(255 ** 2 / ((a - b) ** 2).mean())))" "$out/irr_$s.png" "$out/pov_$s.png"
done

#!/usr/bin/env bash
# Irradia's rasterizer against Mesa llvmpipe (OpenGL on the CPU, through moderngl),
# side by side in one run: 1280x720, depth test, per-vertex (Gouraud) lighting,
# (a) 1M random triangles of about 23 pixels, (b) the gyroid mesh (2,254,088 triangles).
# Runs alternate A B A B; each run times FRAMES frames after one warm-up frame.
#
#   [BIN=raster_bench] bench/raster/run.sh [ROUNDS=5] [FRAMES=3] [THREADS="1 2"]
#
# Prints a markdown summary (medians of the per-run medians, ratio Irradia / llvmpipe,
# fraction of differing pixels) and keeps the raw JSON lines and images in $OUT.
set -euo pipefail
ROUNDS=${1:-5}
FRAMES=${2:-3}
THREADS=${3:-"1 2"}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
OUT=${OUT:-$ROOT/target/bench-raster}
mkdir -p "$OUT"
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$ROOT/target}

if ! python3 -c "import moderngl, numpy, PIL" 2>/dev/null; then
    python3 -m pip install --quiet moderngl glcontext numpy pillow || { echo "skip: moderngl is not available"; exit 0; }
fi
if ! python3 -c "import moderngl; moderngl.create_standalone_context(backend='egl')" 2>/dev/null; then
    (apt-get install -y libegl1 libegl-mesa0 libgl1-mesa-dri libgbm1 >/dev/null 2>&1) || true
    python3 -c "import moderngl; moderngl.create_standalone_context(backend='egl')" 2>/dev/null \
        || { echo "skip: no EGL / llvmpipe context"; exit 0; }
fi

# BIN=path/to/raster_bench times that binary (e.g. a copy of an older build) instead
# of building the worktree's.
if [ -z "${BIN:-}" ]; then
    cargo build --release -p irradia-raster --example raster_bench >&2
    BIN=$CARGO_TARGET_DIR/release/examples/raster_bench
fi
for w in random gyroid; do
    [ -f "$OUT/$w.bin" ] || "$BIN" write "$w" "$OUT/$w.bin"
done

RESULTS=$OUT/results.jsonl
: > "$RESULTS"
echo "load before: $(uptime)" >&2
for w in random gyroid; do
    for t in $THREADS; do
        for r in $(seq 1 "$ROUNDS"); do
            png_i=""; png_l=""
            if [ "$r" = 1 ]; then png_i="$OUT/irradia-$w-$t.png"; png_l="$OUT/llvmpipe-$w-$t.png"; fi
            "$BIN" time "$OUT/$w.bin" "$FRAMES" "$t" $png_i | sed "s/^{/{\"workload\":\"$w\",/" >> "$RESULTS"
            LP_NUM_THREADS=$t python3 "$ROOT/bench/raster/llvmpipe.py" "$OUT/$w.bin" "$FRAMES" $png_l \
                | sed "s/^{/{\"workload\":\"$w\",/" >> "$RESULTS"
            echo "  $w threads=$t round $r/$ROUNDS done" >&2
        done
    done
done
echo "load after: $(uptime)" >&2
python3 "$ROOT/bench/raster/summarize.py" "$RESULTS" "$OUT"

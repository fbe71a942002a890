#!/usr/bin/env bash
# Irradia's rasterizer against Mesa llvmpipe (OpenGL on the CPU, through moderngl),
# side by side in one run: 1280x720, depth test, per-vertex (Gouraud) lighting,
# (a) 1M random triangles of about 23 pixels, (b) the gyroid mesh (2,254,088 triangles).
# Runs alternate A B A B; each run times FRAMES frames after one warm-up frame.
#
#   [BIN=raster_bench] [PIN1=1] bench/raster/run.sh [ROUNDS=5] [FRAMES=3] [THREADS="1 2"]
#
# One thread means one core for both. At LP_NUM_THREADS=1 llvmpipe has one rasterizer
# thread besides the application thread, and they overlap: the rasterizer draws the
# scenes flushed while the application thread still transforms and bins the rest
# (measured per frame inside `vao.render()`, schedstat run times: random 0.10 s of
# rasterizer CPU next to 0.13 s of application CPU, gyroid 0.18 s next to 0.21 s, out
# of 0.8 and 0.55 s of CPU per frame), so unpinned it can keep two cores busy where
# Irradia's one-thread pool keeps one. The 1-thread runs of both programs are therefore
# pinned to the same one core (`taskset -c $PIN_CPU`, CPU 0 unless set); PIN1=0 runs
# them unpinned, as before. Runs at 2 or more threads are not pinned (every core for both).
#
# Prints a markdown summary (medians of the per-run medians, ratio Irradia / llvmpipe,
# each program's CPU time per frame over its wall time, fraction of differing pixels)
# and keeps the raw JSON lines and images in $OUT.
set -euo pipefail
ROUNDS=${1:-5}
FRAMES=${2:-3}
THREADS=${3:-"1 2"}
PIN1=${PIN1:-1}
PIN_CPU=${PIN_CPU:-0}
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
if [ "$PIN1" = 1 ]; then echo "1-thread runs of both programs pinned to CPU $PIN_CPU (taskset)" >&2; fi
for w in random gyroid; do
    for t in $THREADS; do
        pin=""; pinned=false
        if [ "$t" = 1 ] && [ "$PIN1" = 1 ]; then pin="taskset -c $PIN_CPU"; pinned=true; fi
        tag="s/^{/{\"workload\":\"$w\",\"pinned\":$pinned,/"
        for r in $(seq 1 "$ROUNDS"); do
            png_i=""; png_l=""
            if [ "$r" = 1 ]; then png_i="$OUT/irradia-$w-$t.png"; png_l="$OUT/llvmpipe-$w-$t.png"; fi
            $pin "$BIN" time "$OUT/$w.bin" "$FRAMES" "$t" $png_i | sed "$tag" >> "$RESULTS"
            env LP_NUM_THREADS="$t" $pin python3 "$ROOT/bench/raster/llvmpipe.py" "$OUT/$w.bin" "$FRAMES" $png_l \
                | sed "$tag" >> "$RESULTS"
            echo "  $w threads=$t round $r/$ROUNDS done" >&2
        done
    done
done
echo "load after: $(uptime)" >&2
python3 "$ROOT/bench/raster/summarize.py" "$RESULTS" "$OUT"

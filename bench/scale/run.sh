#!/usr/bin/env bash
# Calibrates the alpha-beta network model on this machine (MPI ping-pong between two
# ranks through Irradia's Comm) and prints `irradia bench scale`'s predictions at 64 to
# 32,768 ranks with it, then with gigabit ethernet and with a Blue Gene/P torus link
# (425 MB/s a direction, 3 us; Kendall et al.'s machine), for docs/benchmarks.md.
#   bash bench/scale/run.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
command -v mpirun >/dev/null || { echo "scale bench: mpirun not found (apt-get install openmpi-bin libopenmpi-dev libclang-dev)"; exit 1; }
export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-target}
cargo build --release --locked -q -p irradia-parallel --features mpi --example pingpong
cargo build --release --locked -q -p irradia
MPIRUN=(mpirun --oversubscribe --bind-to none)
if [ "$(id -u)" = 0 ]; then MPIRUN+=(--allow-run-as-root); fi
echo "date: $(date -u +%Y-%m-%dT%H:%MZ)  machine: $(nproc) cores  load: $(uptime | sed 's/.*load/load/')"
out=$("${MPIRUN[@]}" -np 2 "$CARGO_TARGET_DIR/release/examples/pingpong")
echo "$out"
alpha=$(sed -nE 's/RESULT alpha_us=([0-9.]+).*/\1/p' <<<"$out")
mbit=$(sed -nE 's/.*bandwidth_mbit=([0-9.]+).*/\1/p' <<<"$out")
BIN="$CARGO_TARGET_DIR/release/irradia"
echo; echo "## this machine's MPI (shared memory), calibrated above"
"$BIN" bench scale --latency-us "$alpha" --bandwidth-mbit "$mbit"
echo; echo "## gigabit ethernet (50 us, 1000 Mbit/s)"
"$BIN" bench scale
echo; echo "## Blue Gene/P torus link (3 us, 425 MB/s = 3400 Mbit/s)"
"$BIN" bench scale --latency-us 3 --bandwidth-mbit 3400

#!/usr/bin/env bash
# Shared driver: bench.sh BUILTIN POV_FILE RUNS. Installs missing peers where it can,
# skips cleanly where it cannot, builds Irradia in release mode and runs compare.py.
set -euo pipefail
scene="$1"; pov="$2"; runs="$3"
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"

need() {
    command -v "$1" >/dev/null 2>&1 && return 0
    echo "installing $1 ..." >&2
    if command -v apt-get >/dev/null 2>&1; then
        (apt-get install -y "$2" >/dev/null 2>&1 || { apt-get update >/dev/null 2>&1 && apt-get install -y "$2" >/dev/null 2>&1; }) || true
    fi
    command -v "$1" >/dev/null 2>&1 || { echo "SKIP: $1 is not available" >&2; exit 0; }
}
need povray povray
need hyperfine hyperfine
python3 -c "import numpy, PIL" 2>/dev/null || python3 -m pip install -q numpy pillow || {
    echo "SKIP: python3 with numpy and pillow is not available" >&2; exit 0; }

cd "$root"
cargo build --release -q -p irradia
bin="${CARGO_TARGET_DIR:-$root/target}/release/irradia"
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo); $(date -u +%Y-%m-%dT%H:%MZ)"
echo "povray: $(povray --version 2>&1 | grep -m1 -o 'POV-Ray [0-9.]*' || echo unknown)"
echo "load: $(cat /proc/loadavg)"
python3 "$here/compare.py" "$bin" "$scene" "$pov" --runs "$runs"

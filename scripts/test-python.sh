#!/usr/bin/env bash
# The Python package's tests: builds the irradia wheel (crates/python, maturin) into a
# virtual environment and runs pytest on crates/python/tests, comparing arrays with the
# `irradia` command's output; then the compositing tests under mpirun -np 2..4 (np 1
# runs in the plain pytest run) when OpenMPI and mpi4py are there.
#
# Without python3's venv or pip it says so and skips; under CI (CI set to anything but
# "" or "false") or with IRRADIA_REQUIRE_PYTHON=1 that is a failure. The MPI part
# follows IRRADIA_REQUIRE_MPI like scripts/test-mpi.sh.
#
# The wheel and the command it is compared with are built with the dev profile into the
# workspace's target folder (CARGO_TARGET_DIR): dependencies are compiled with
# opt-level 2 there, shared with `cargo test`, and only the workspace's own crates are
# compiled again (at opt-level 0; both sides the same build, so the arrays compare bit
# for bit). maturin cannot use the test profile: `cargo rustc --profile test` builds a
# test harness. The venv lives in the target folder too (IRRADIA_PY_VENV to choose
# another) and is reused between runs.
set -uo pipefail
cd "$(dirname "$0")/.."
flag() { [ "${!1:-0}" = 1 ] || { [ -n "${CI:-}" ] && [ "${CI:-}" != false ]; }; }
skip_or_fail() {
  if flag IRRADIA_REQUIRE_PYTHON; then
    echo "test-python: $1, and the Python tests are required here (CI=${CI:-} IRRADIA_REQUIRE_PYTHON=${IRRADIA_REQUIRE_PYTHON:-0})"
    exit 1
  fi
  echo "test-python: $1; skipping the Python tests"
  exit 0
}
command -v python3 >/dev/null 2>&1 || skip_or_fail "python3 not found"
target="${CARGO_TARGET_DIR:-$PWD/target}"
venv="${IRRADIA_PY_VENV:-$target/python-venv}"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >/dev/null 2>&1 || { rm -rf "$venv"; skip_or_fail "python3 -m venv failed (apt-get install python3-venv)"; }
fi
py="$venv/bin/python"
"$py" -m pip --version >/dev/null 2>&1 || skip_or_fail "pip is missing in the venv (apt-get install python3-pip)"
need=()
"$py" -c "import numpy" 2>/dev/null || need+=(numpy)
"$py" -c "import pytest" 2>/dev/null || need+=(pytest)
[ -x "$venv/bin/maturin" ] || need+=("maturin>=1.5,<2")
# Features given here replace pyproject.toml's list: name extension-module too.
features=(--features extension-module)
have_mpi=0
if command -v mpirun >/dev/null 2>&1 && command -v mpicc >/dev/null 2>&1; then
  have_mpi=1
  features=(--features extension-module,mpi)
  "$py" -c "import mpi4py" 2>/dev/null || need+=(mpi4py)
elif flag IRRADIA_REQUIRE_MPI; then
  echo "test-python: mpirun/mpicc not found and the MPI tests are required here"
  exit 1
fi
if [ ${#need[@]} -gt 0 ]; then
  echo "test-python: pip install ${need[*]}"
  "$py" -m pip install -q "${need[@]}" || skip_or_fail "pip install ${need[*]} failed"
fi

# The command the arrays are compared with, and the wheel (no auditwheel repair: the
# MPI build must use the system's libmpi, the one mpi4py uses).
cargo build --locked -p irradia 2>&1 || { echo "test-python: building irradia failed"; exit 1; }
wheels="$(mktemp -d)"
trap 'rm -rf "$wheels"' EXIT
( cd crates/python && CARGO_TARGET_DIR="$target" "$venv/bin/maturin" build \
    "${features[@]}" --auditwheel skip -i "$py" -o "$wheels" ) 2>&1 \
  || { echo "test-python: building the wheel failed"; exit 1; }
"$py" -m pip install -q --force-reinstall --no-deps "$wheels"/irradia-*.whl \
  || { echo "test-python: installing the wheel failed"; exit 1; }

export IRRADIA_BIN="$target/debug/irradia" IRRADIA_REQUIRE_CLI=1
[ "$have_mpi" = 1 ] && export IRRADIA_REQUIRE_MPI="${IRRADIA_REQUIRE_MPI:-0}"
cd crates/python
status=0
"$py" -m pytest -q -p no:cacheprovider tests || status=1
if [ "$have_mpi" = 1 ]; then
  MPIRUN=(mpirun --oversubscribe)
  if [ "$(id -u)" = 0 ]; then MPIRUN+=(--allow-run-as-root); fi
  for np in 2 3 4; do
    if out=$(timeout 300 "${MPIRUN[@]}" -np "$np" "$py" -m pytest -q -p no:cacheprovider tests/test_composite_mpi.py 2>&1); then
      echo "test-python: composite under mpirun -np $np: $(echo "$out" | grep -E 'passed|skipped' | tail -n 1)"
      if echo "$out" | grep -q skipped && flag IRRADIA_REQUIRE_MPI; then status=1; fi
    else
      echo "$out" | tail -n 30
      echo "test-python: composite under mpirun -np $np FAILED"
      status=1
    fi
  done
  if out=$(timeout 300 "${MPIRUN[@]}" -np 3 "$py" ../../examples/python/sort_last_volume.py --size 32 2>&1); then
    echo "test-python: examples/python/sort_last_volume.py under mpirun -np 3: $(echo "$out" | tail -n 1)"
  else
    echo "$out" | tail -n 30
    echo "test-python: examples/python/sort_last_volume.py under mpirun -np 3 FAILED"
    status=1
  fi
fi
exit $status

#!/usr/bin/env bash
# Runs every test of the workspace (unit, integration, property and image tests), then
# the MPI tests under mpirun (skipped with a message when OpenMPI is missing, except
# under CI or with IRRADIA_REQUIRE_MPI=1, where that fails the run), then the Python
# package's tests (scripts/test-python.sh: skipped without python3 venv/pip, except
# under CI or with IRRADIA_REQUIRE_PYTHON=1).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --locked 2>&1
bash scripts/test-mpi.sh
bash scripts/test-python.sh

#!/usr/bin/env bash
# Runs every test of the workspace (unit, integration, property and image tests), then
# the MPI tests under mpirun when OpenMPI is installed.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --workspace --locked 2>&1
if [ -x scripts/test-mpi.sh ]; then
  bash scripts/test-mpi.sh
fi

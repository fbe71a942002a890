#!/usr/bin/env bash
# Builds the release binary target/release/irradia: with MPI (`irradia render`,
# `parallel` and `wall` with `--comm mpi` under mpirun) when OpenMPI and libclang are
# installed, without it (and saying how to get it) when they are not.
set -euo pipefail
cd "$(dirname "$0")/.."
have_libclang() { ls /usr/lib/llvm-*/lib/libclang*.so* >/dev/null 2>&1 || ldconfig -p 2>/dev/null | grep -q libclang; }
features=()
if command -v mpicc >/dev/null 2>&1 && command -v mpirun >/dev/null 2>&1 && have_libclang; then
  echo "build: OpenMPI found: building with MPI (--comm mpi)" >&2
  features=(--features mpi)
else
  echo "build: OpenMPI (mpicc, mpirun) or libclang not found: building without MPI." >&2
  echo "build: for --comm mpi install them (Debian/Ubuntu: sudo apt-get install openmpi-bin libopenmpi-dev libclang-dev) and run this again." >&2
fi
cargo build --release --locked -p irradia "${features[@]}"

#!/usr/bin/env bash
# The MPI tests: builds irradia-parallel with --features mpi and runs the compositing
# check (every strategy, opaque bit-exact and ordered "over") under mpirun for 1 to 16
# ranks, the parallel ray tracer at 2 and 3 ranks and the tiled wall at 4. On a
# developer's machine without OpenMPI it says so and skips; under CI (CI set to anything
# but "" or "false") or with IRRADIA_REQUIRE_MPI=1 a missing mpirun is a failure, so
# the MPI tests can never vanish from a CI run unnoticed. Exits non-zero on any failure
# and ends with a line "N passed, N failed" (one count per mpirun launch).
set -uo pipefail
cd "$(dirname "$0")/.."
require_mpi() { [ "${IRRADIA_REQUIRE_MPI:-0}" = 1 ] || { [ -n "${CI:-}" ] && [ "${CI:-}" != false ]; }; }
if ! command -v mpirun >/dev/null 2>&1; then
  if require_mpi; then
    echo "test-mpi: mpirun not found, and the MPI tests are required here (CI=${CI:-} IRRADIA_REQUIRE_MPI=${IRRADIA_REQUIRE_MPI:-0}); install openmpi-bin libopenmpi-dev libclang-dev"
    echo "test-mpi: 0 passed, 1 failed"
    exit 1
  fi
  echo "test-mpi: mpirun not found; skipping the MPI tests (apt-get install openmpi-bin libopenmpi-dev libclang-dev)"
  exit 0
fi
# The test profile (opt-level 2, no LTO) shares its dependencies with `cargo test`.
if ! cargo build --locked --profile test -p irradia-parallel --features mpi --example mpi_check --example mpi_raytrace_check 2>&1; then
  echo "test-mpi: build failed"
  echo "0 passed, 1 failed"
  exit 1
fi
dir="${CARGO_TARGET_DIR:-target}/debug/examples"
MPIRUN=(mpirun --oversubscribe)
if [ "$(id -u)" = 0 ]; then MPIRUN+=(--allow-run-as-root); fi
passed=0
failed=0
for np in $(seq 1 16); do
  if out=$(timeout 120 "${MPIRUN[@]}" -np "$np" "$dir/mpi_check" 2>&1); then
    passed=$((passed + 1))
    echo "$out" | tail -n 1
  else
    failed=$((failed + 1))
    echo "$out" | grep -v '^ok' | tail -n 20
    echo "test-mpi: np=$np FAILED"
  fi
done
# The parallel ray tracer (image- and object-parallel) against the serial render.
for np in 2 3; do
  if out=$(timeout 120 "${MPIRUN[@]}" -np "$np" "$dir/mpi_raytrace_check" 2>&1); then
    passed=$((passed + 1))
    echo "$out" | tail -n 1
  else
    failed=$((failed + 1))
    echo "$out" | grep -v '^ok' | tail -n 20
    echo "test-mpi: ray tracer np=$np FAILED"
  fi
done
# The tiled wall over MPI equals the threads' run, per display and sort-last.
if ! cargo build --locked --profile test -p irradia-parallel --features mpi --example mpi_wall_check 2>&1; then
  failed=$((failed + 1))
  echo "test-mpi: wall build FAILED"
elif out=$(timeout 120 "${MPIRUN[@]}" -np 4 "$dir/mpi_wall_check" 2>&1); then
  passed=$((passed + 1))
  echo "$out" | grep '^ok'
else
  failed=$((failed + 1))
  echo "$out" | tail -n 20
  echo "test-mpi: wall np=4 FAILED"
fi
echo "test-mpi: $passed passed, $failed failed"
[ "$failed" -eq 0 ]

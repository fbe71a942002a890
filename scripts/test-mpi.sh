#!/usr/bin/env bash
# The MPI tests: builds irradia-parallel with --features mpi and runs the compositing
# check (every strategy, opaque bit-exact and ordered "over") under mpirun for 1 to 16
# ranks, the parallel ray tracer at 2 and 3 ranks, the tiled wall at 4, and the
# distributed `irradia render` and `irradia radiosity --solver hierarchical` at 1 to 8. On a
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
# Everything the checks below run, in one build: the test profile (opt-level 2, no LTO)
# with the workspace's own feature resolution (`--workspace`, the feature named by its
# package, and examples among the targets so dev-dependencies count as they do for
# `cargo test`) shares every compiled crate with `cargo test --workspace`; only
# irradia-parallel and what depends on it are compiled again with MPI (crates/core's
# Cargo.toml gives `syn` the one feature MPI's bindgen adds).
if ! cargo build --locked --profile test --workspace --features irradia/mpi --bin irradia \
    --example mpi_check --example mpi_raytrace_check --example mpi_wall_check 2>&1; then
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
if out=$(timeout 120 "${MPIRUN[@]}" -np 4 "$dir/mpi_wall_check" 2>&1); then
  passed=$((passed + 1))
  echo "$out" | grep '^ok'
else
  failed=$((failed + 1))
  echo "$out" | tail -n 20
  echo "test-mpi: wall np=4 FAILED"
fi
# One image on N ranks (`irradia render --comm mpi`): equal to the one-process render
# bit for bit (image and AOV) at 1 to 8 ranks, path tracer and Whitted tracer; and a
# rank killed mid-render ends the job (no hang) with an error naming it, no output file.
bin="${CARGO_TARGET_DIR:-target}/debug/irradia"
if [ ! -x "$bin" ]; then
  failed=$((failed + 1))
  echo "test-mpi: $bin (built with MPI above) is missing: FAILED"
else
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  small=(--width 48 --height 40 --threads 1 --tile-size 16 --quiet --aov depth)
  "$bin" render --builtin cornell --spp 6 "${small[@]}" -o "$tmp/serial.pfm"
  "$bin" render --builtin whitted --spp 4 "${small[@]}" -o "$tmp/whitted.pfm"
  for np in 1 2 3 4 5 6 7 8; do
    if timeout 120 "${MPIRUN[@]}" -np "$np" "$bin" render --builtin cornell --spp 6 "${small[@]}" --comm mpi -o "$tmp/np$np.pfm" \
      && cmp -s "$tmp/serial.pfm" "$tmp/np$np.pfm" && cmp -s "$tmp/serial.depth.pfm" "$tmp/np$np.depth.pfm"; then
      passed=$((passed + 1))
      echo "ok render --comm mpi np=$np: path-traced image and depth equal the one-process render"
    else
      failed=$((failed + 1))
      echo "test-mpi: render --comm mpi np=$np FAILED"
    fi
  done
  if timeout 120 "${MPIRUN[@]}" -np 3 "$bin" render --builtin whitted --spp 4 "${small[@]}" --comm mpi -o "$tmp/w3.pfm" \
    && cmp -s "$tmp/whitted.pfm" "$tmp/w3.pfm"; then
    passed=$((passed + 1))
    echo "ok render --comm mpi np=3: Whitted image equals the one-process render"
  else
    failed=$((failed + 1))
    echo "test-mpi: render --comm mpi whitted np=3 FAILED"
  fi
  # Kill rank 1 a second into a job that would otherwise take hours: the job must end
  # (no hang: 124) with an error naming rank 1 and leave no output file.
  # kill_rank1 NAME PATTERN WHAT ARGS...: PATTERN finds the job's processes (pgrep -f).
  kill_rank1() {
    local name=$1 pattern=$2 what=$3; shift 3
    ( RAYON_NUM_THREADS=1 timeout 120 "${MPIRUN[@]}" -np 3 "$bin" "$@" -o "$tmp/$name.png" >"$tmp/$name.log" 2>&1; echo $? >"$tmp/$name.rc" ) &
    local job=$! pid="" p rc
    for _ in $(seq 1 200); do
      for p in $(pgrep -f "$pattern" || true); do
        if tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=1'; then pid=$p; fi
      done
      [ -n "$pid" ] && break
      sleep 0.1
    done
    sleep 1
    [ -n "$pid" ] && kill -9 "$pid"
    wait "$job"
    rc=$(cat "$tmp/$name.rc")
    if [ -n "$pid" ] && [ "$rc" != 0 ] && [ "$rc" != 124 ] && grep -q "rank 1" "$tmp/$name.log" && [ ! -e "$tmp/$name.png" ]; then
      passed=$((passed + 1))
      echo "ok $what: rank 1 killed mid-run ends the job (exit $rc) naming rank 1, no output file"
    else
      failed=$((failed + 1))
      echo "test-mpi: $what killed rank FAILED (pid '$pid', exit $rc; 124 is a hang)"
      tail -n 20 "$tmp/$name.log"
    fi
  }
  kill_rank1 killed "irradia render --builtin cornell --width 256" "render --comm mpi" \
    render --builtin cornell --width 256 --height 256 --spp 60000 --threads 1 --quiet --comm mpi
  # Hierarchical radiosity on N ranks (`irradia radiosity --solver hierarchical --comm
  # mpi`): the image (PFM), the solved mesh (PLY) and the change per iteration (CSV,
  # shortest round-trip decimals of each f64) equal the one-process run at 1 to 8 ranks;
  # and a rank killed mid-solve ends the job (no hang) with an error naming it, no output.
  hrad=(radiosity --solver hierarchical --elements 3000 --width 64 --height 64 --quiet)
  RAYON_NUM_THREADS=1 "$bin" "${hrad[@]}" -o "$tmp/hrad.pfm" --mesh-out "$tmp/hrad.ply" --convergence "$tmp/hrad.csv"
  for np in 1 2 3 4 5 6 7 8; do
    if RAYON_NUM_THREADS=1 timeout 120 "${MPIRUN[@]}" -np "$np" "$bin" "${hrad[@]}" --comm mpi \
        -o "$tmp/hrad$np.pfm" --mesh-out "$tmp/hrad$np.ply" --convergence "$tmp/hrad$np.csv" \
      && cmp -s "$tmp/hrad.pfm" "$tmp/hrad$np.pfm" && cmp -s "$tmp/hrad.ply" "$tmp/hrad$np.ply" \
      && cmp -s "$tmp/hrad.csv" "$tmp/hrad$np.csv"; then
      passed=$((passed + 1))
      echo "ok radiosity --comm mpi np=$np: image, mesh and iteration history equal the one-process solve"
    else
      failed=$((failed + 1))
      echo "test-mpi: radiosity --comm mpi np=$np FAILED"
    fi
  done
  kill_rank1 hkilled "irradia radiosity --solver hierarchical --elements 300000" "radiosity --comm mpi" \
    radiosity --solver hierarchical --elements 300000 --quiet --comm mpi
fi
echo "test-mpi: $passed passed, $failed failed"
[ "$failed" -eq 0 ]

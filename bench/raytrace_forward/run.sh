#!/usr/bin/env bash
# Object-parallel Whitted ray tracing with ray forwarding against the image-parallel
# form, on the built-in default scene (area light, glass, mirror, CSG; 7 objects):
# wall time, generations and bytes forwarded, at 2 and 4 ranks (threads, LocalComm).
# Usage: bench/raytrace_forward/run.sh [IRRADIA] [WIDTH HEIGHT] [RUNS]
# Prints one line per run (interleaved) and the medians. Needs python3.
set -euo pipefail
bin=${1:-target/release/irradia}
w=${2:-320}
h=${3:-180}
runs=${4:-3}
[ -x "$bin" ] || { echo "no irradia binary at $bin (cargo build --release -p irradia)"; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "# $(date -u +%FT%TZ) $(nproc) cores; load: $(uptime | sed 's/.*load average: //')"
"$bin" render --width "$w" --height "$h" -o "$tmp/serial.pfm" --quiet
for i in $(seq "$runs"); do
  for ranks in 2 4; do
    for form in sort-first forward; do
      case $form in
        sort-first) args=(--mode sort-first) ;;
        forward) args=(--mode sort-last --object-shading forward) ;;
      esac
      start=$(date +%s.%N)
      "$bin" parallel "${args[@]}" --renderer raytrace --workload builtin:default \
        --width "$w" --height "$h" --ranks "$ranks" -o "$tmp/$form.pfm" \
        --report "$tmp/$form.json" --quiet
      end=$(date +%s.%N)
      python3 - "$tmp" "$form" "$ranks" "$start" "$end" <<'PY'
import json, sys
tmp, form, ranks, start, end = sys.argv[1:]
r = json.load(open(f"{tmp}/{form}.json"))
same = open(f"{tmp}/{form}.pfm", "rb").read() == open(f"{tmp}/serial.pfm", "rb").read()
sent = sum(s.get("total_bytes_sent", 0) for s in r.get("stages", []))
f = r.get("balance", {}).get("forwarding")
gens = f["generations"] if f else "-"
print(f"{form:10} ranks {ranks}  {float(end) - float(start):7.3f} s  bytes sent {sent:>11}  generations {gens}  equals serial: {same}")
PY
    done
  done
done | tee "$tmp/lines"
echo "# medians"
python3 - "$tmp/lines" <<'PY'
import sys, statistics, collections
t = collections.defaultdict(list)
for line in open(sys.argv[1]):
    p = line.split()
    t[(p[0], p[2])].append(float(p[3]))
for (form, ranks), v in sorted(t.items()):
    print(f"{form:10} ranks {ranks}: median {statistics.median(v):.3f} s over {len(v)} runs")
PY
if grep -q "equals serial: False" "$tmp/lines"; then
  echo "FAILED: an image differs from the serial render"
  exit 1
fi

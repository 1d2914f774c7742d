#!/usr/bin/env bash
# texsim's functional texture unit beside Mesa's llvmpipe and softpipe on the same grazing
# checkerboard floor (testbench/bench/bench_peers.cc): bilinear and trilinear fragments/s on
# one core, measured side by side in one run (REPEAT repetitions, randomly interleaved, median
# of each), and the ratios. llvmpipe runs on the calling thread (LP_NUM_THREADS=0). When Mesa
# cannot start (no EGL/OpenGL at build time, no Mesa drivers), its columns say why.
# Usage: scripts/bench-peers.sh [BUILD_DIR] [REPEAT]
set -euo pipefail
cd "$(dirname "$0")/.."
bench=${1:-build}/testbench/bench_peers
repeat=${2:-5}
if [ ! -x "$bench" ]; then
  echo "bench-peers: $bench not found (cmake --build ${1:-build} --target bench_peers)" >&2
  exit 2
fi
json=$(mktemp)
trap 'rm -f "$json"' EXIT
LP_NUM_THREADS=0 "$bench" --benchmark_repetitions="$repeat" \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \
  --benchmark_format=json --benchmark_out="$json" --benchmark_out_format=json > /dev/null 2>&1 || true
python3 - "$json" "$repeat" <<'PY'
import json, sys
data = json.load(open(sys.argv[1]))
rate, single, why, label = {}, {}, {}, {}
for b in data["benchmarks"]:
    name = b.get("run_name", b["name"]).split("/")[0]
    if b.get("error_occurred"):
        why[name] = b.get("error_message", "error")
    elif b.get("aggregate_name") == "median":
        rate[name] = b["items_per_second"] / 1e6
    elif b.get("run_type") == "iteration":  # one repetition: no aggregates
        single[name] = b["items_per_second"] / 1e6
        label[name] = b.get("label", "")
    if b.get("label"):
        label[name] = b["label"]
for name, r in single.items():
    rate.setdefault(name, r)
peers = ["Llvmpipe", "Softpipe"]
print(f"Fragments/s on one core, bench_peers, median of {sys.argv[2]} interleaved repetitions")
for p in peers:
    for m in ("Bilinear", "Trilinear"):
        n = f"BM_{p}_{m}"
        if n in label:
            print(f"  {p.lower()}: {label[n]}")
            break
print(f"{'':10} {'texsim':>10} {'llvmpipe':>10} {'softpipe':>10} {'texsim/llvmpipe':>16} {'texsim/softpipe':>16}")
for m in ("Bilinear", "Trilinear"):
    t = rate.get(f"BM_Texsim_{m}")
    cells = [f"{t:8.1f} M" if t else "—"]
    ratios = []
    for p in peers:
        r = rate.get(f"BM_{p}_{m}")
        cells.append(f"{r:8.1f} M" if r else "n/a")
        ratios.append(f"{t / r:.2f}" if (t and r) else "n/a")
    print(f"{m.lower():10} {cells[0]:>10} {cells[1]:>10} {cells[2]:>10} {ratios[0]:>16} {ratios[1]:>16}")
for p in peers:
    for m in ("Bilinear", "Trilinear"):
        n = f"BM_{p}_{m}"
        if n in why:
            print(f"{p.lower()} not measured: {why[n]}")
            break
PY

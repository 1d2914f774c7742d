#!/usr/bin/env bash
# Process start-up of texsim: runs `texsim --version`, `texsim trace info` on a shipped sample
# trace, and `texsim run` of a scene with procedural textures only (--reference none, at 16x16
# so that start-up dominates, and at its own size) N times each, and prints the minimum and
# median wall time and the largest peak RSS per case. Each process is started with
# posix_spawn and reaped with wait4, so the times hold the process alone, not a shell's fork.
# With BASELINE=OTHER_TEXSIM the other binary runs the same cases, alternating run by run with
# this one, and both columns are printed side by side (the before/after of docs/performance.md).
# Usage: [BASELINE=OLD_TEXSIM] scripts/bench-startup.sh [BUILD_DIR] [N]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${1:-build}")/texsim
runs=${2:-50}
base=${BASELINE:+$(realpath "$BASELINE")}
[[ -x $bin ]] || { echo "bench-startup: no texsim at $bin (build it first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

field() { grep -m1 "^$1" /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'; }
echo "CPU: $(field 'model name'), vendor $(field vendor_id), family $(field 'cpu family')" \
  "model $(field 'model\s'), $(uname -m), $(nproc) cores; ISA:" \
  "$(for f in avx2 avx512f; do grep -qw "$f" /proc/cpuinfo && printf '%s ' "$f"; done)"
echo "runs per case: $runs; binary: $bin${base:+; baseline: $base}"

python3 - "$work" "$runs" "$bin" ${base:+"$base"} <<'EOF'
import os, statistics, sys, time

work, runs, bins = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
scene = "scenes/coords.toml"  # procedural textures only
cases = [
    ("--version", ["--version"]),
    ("trace info traces/samples/basic.trc", ["trace", "info", "traces/samples/basic.trc"]),
    ("run coords.toml at 16x16, --reference none",
     ["run", scene, "--reference", "none", "--no-progress", "--set", "output.width=16",
      "--set", "output.height=16"]),
    ("run coords.toml (480x240), --reference none",
     ["run", scene, "--reference", "none", "--no-progress"]),
]
null = os.open(os.devnull, os.O_WRONLY)


def once(binary, args, out):
    argv = [binary] + args + (["--out", out] if args[0] == "run" else [])
    fa = [(os.POSIX_SPAWN_DUP2, null, 1), (os.POSIX_SPAWN_DUP2, null, 2)]
    t0 = time.perf_counter_ns()
    pid = os.posix_spawn(binary, argv, os.environ, file_actions=fa)
    _, status, usage = os.wait4(pid, 0)
    t1 = time.perf_counter_ns()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"bench-startup: {' '.join(argv)} failed (exit {status})")
    return (t1 - t0) / 1e6, usage.ru_maxrss / 1024  # ms, MiB


def cell(samples):
    ms = [s[0] for s in samples]
    return f"{min(ms):8.1f} {statistics.median(ms):8.1f} {max(s[1] for s in samples):7.1f}"


head = "min ms   med ms  RSS MiB"
print(f"\n{'case':46} | {'new: ' + head if len(bins) > 1 else head}"
      + (f" | old: {head}" if len(bins) > 1 else ""))
for label, args in cases:
    samples = [[] for _ in bins]
    for i in range(runs):
        for k, b in enumerate(bins):  # alternate, so that drift hits both alike
            samples[k].append(once(b, args, os.path.join(work, f"out{k}")))
    print(f"{label:46} | " + " | ".join(cell(s) for s in samples))
EOF

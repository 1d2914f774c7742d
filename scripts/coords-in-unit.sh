#!/usr/bin/env bash
# Times each coordinate method inside the clocked texture unit: scenes/coords.toml with every
# `coords` table set to one method (float, 2x2-quad derivatives), spatial and shared datapath.
# Prints a Markdown table (docs/studies/study-coords.md, "In the texture unit").
# Usage: scripts/coords-in-unit.sh [BUILD_DIR]   (default: build)
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="${1:-$here/build}/texsim"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
echo "| method | datapath | cycles | cycles/fragment | coords ops/pixel | coords stage busy | cache stage busy |"
echo "|---|---|---|---|---|---|---|"
for m in heckbert heckbert-rcp incremental incremental-k4 constant-depth quadratic-32; do
  for dp in spatial shared; do
    sed -E "s/^coords = \{[^}]*\}/coords = { method = \"$m\", derivs = \"quad\", format = \"float\", datapath = \"$dp\" }/" \
      "$here/scenes/coords.toml" > "$tmp/scene.toml"
    "$bin" run "$tmp/scene.toml" --out "$tmp/out" --no-progress > /dev/null
    awk -v m="$m" -v dp="$dp" -F'|' '
      /^\| cycles \|/ { split($3, a, " "); cycles = a[1]; cpf = a[2]; gsub(/\(/, "", cpf) }
      /^Coordinate front end:/ { split($0, w, " "); generated = w[4] }
      /^\| coords\./ { ops = 0; for (k = 7; k <= 14; ++k) ops += $k; coords_ops += ops }
      /^\| coords \|/ { cu = $4 }
      /^\| cache \|/ && NF > 8 { ca = $4 }
      END { printf "| %s | %s | %s | %s | %.2f | %s | %s |\n", m, dp, cycles, cpf, coords_ops / generated, cu, ca }
    ' "$tmp/out/report.md"
  done
done

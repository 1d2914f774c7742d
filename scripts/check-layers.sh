#!/usr/bin/env bash
# Checks the one-way dependency rule between folders (docs/architecture.md, "Layers"):
# a file may include a file of its own layer or of a lower one, never of a higher one.
# Usage: scripts/check-layers.sh [SOURCE_DIR]. Prints every offending include; exit 1 if any.
set -euo pipefail
cd "${1:-$(dirname "$0")/..}"

# layer of a path: "rank group"; a file may include the same group or a lower rank.
layer() {
  case "$1" in
    rtl_model/number/*|blocks/base/*) echo "0 base" ;;
    blocks/*) echo "1 blocks" ;;
    traces/*) echo "1 traces" ;;
    rtl_model/*) echo "2 rtl" ;;
    pipeline/capture/*) echo "2 capture" ;;
    pipeline/image_io/*) echo "2 image_io" ;;
    pipeline/kernel/*) echo "3 kernel" ;;
    pipeline/scene/*) echo "4 scene" ;;
    pipeline/geometry/*) echo "5 geometry" ;;
    pipeline/texture/*) echo "6 texture" ;;
    pipeline/raster/*) echo "7 raster" ;;
    pipeline/render/*) echo "9 render" ;;
    pipeline/reference/*) echo "8 reference" ;;
    pipeline/report/*) echo "9 report" ;;
    pipeline/studies/*) echo "10 studies" ;;
    pipeline/app/*) echo "11 app" ;;
    python/*) echo "12 python" ;;
    testbench/*) echo "99 testbench" ;;
    *) echo "unknown" ;;
  esac
}

bad=0
while IFS= read -r file; do
  read -r frank fgroup <<< "$(layer "$file")"
  while IFS= read -r inc; do
    l=$(layer "$inc")
    if [ "$l" = unknown ]; then
      echo "$file: includes \"$inc\", which is in no known layer"; bad=1; continue
    fi
    read -r irank igroup <<< "$l"
    if [ "$igroup" != "$fgroup" ] && [ "$irank" -ge "$frank" ]; then
      echo "$file: includes \"$inc\" ($igroup, layer $irank) from $fgroup (layer $frank)"
      bad=1
    fi
  done < <(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$file")
done < <(git ls-files 2>/dev/null '*.h' '*.cc' || find blocks traces pipeline rtl_model testbench \( -name '*.h' -o -name '*.cc' \))
if [ "$bad" -ne 0 ]; then
  echo "check-layers: includes against the layer order (docs/architecture.md)"; exit 1
fi
echo "check-layers: every include flows one way"

#!/usr/bin/env bash
# The install as a user gets it (docs/install.md), from an already built tree, no rebuild:
#   scripts/test-install.sh prefix BUILD_DIR [python|no-python]   cmake --install into a temporary prefix, then
#     (a) an outside project (testbench/install/) finds the package and runs one block,
#     (b) the Python module imports from the install and runs a shipped scene,
#     (c) the installed texsim runs a shipped scene (--functional, small).
#   scripts/test-install.sh deb BUILD_DIR [python|no-python]      cpack -G DEB into a temporary directory; the
#     package must hold the binary, man page, module and CMake package, and its binary and
#     module must run where it is unpacked.
# no-python: the build has no Python module (TEXSIM_PYTHON=OFF or no pybind11); not checked.
set -euo pipefail
mode=$1
build=$(cd "$2" && pwd)
src=$(cd "$(dirname "$0")/.." && pwd)
with_python=${3:-python}
tmp=$(mktemp -d "${TMPDIR:-/tmp}/texsim-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
python=${TEXSIM_PYTHON:-/usr/bin/python3}
step() {
  local t0
  t0=$(date +%s.%N)
  "$@"
  printf 'test-install: %s took %.1f s\n' "$*" "$(echo "$(date +%s.%N) - $t0" | bc)"
}

prefix_test() {
  local prefix=$tmp/prefix
  step cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
  # (a) find_package(texsim) and texsim::blocks from an outside project.
  step cmake -S "$src/testbench/install" -B "$tmp/probe" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release > "$tmp/probe-configure.log"
  step cmake --build "$tmp/probe" > "$tmp/probe-build.log"
  step "$tmp/probe/install_probe"
  # (b) the module from the install, not from the build tree.
  [ "$with_python" = python ] && module_test "$prefix"
  # (c) the installed binary on a shipped scene.
  step "$prefix/bin/texsim" run "$prefix/share/texsim/scenes/cube.toml" --functional \
    --set output.width=64 --set output.height=48 --out "$tmp/run"
  [ -s "$tmp/run/report.json" ] || { echo "test-install: no report.json"; exit 1; }
  for f in share/man/man1/texsim.1 share/bash-completion/completions/texsim \
      share/doc/texsim/install.md include/texsim/blocks/base/fragment.h; do
    [ -f "$prefix/$f" ] || { echo "test-install: $f not installed"; exit 1; }
  done
}

module_test() {
  local prefix=$1 module_dir
  module_dir=$(find "$prefix" -path '*/dist-packages/texsim*.so' -printf '%h\n' | head -1)
  [ -n "$module_dir" ] || { echo "test-install: no module under $prefix"; exit 1; }
  step env -u TEXSIM_OIIO_PLUGIN PYTHONPATH="$module_dir" "$python" -c "
import sys, texsim
assert texsim.__file__.startswith('$prefix'), texsim.__file__
r = texsim.run('$prefix/share/texsim/scenes/cube.toml', functional=True,
               overrides={'output.width': 64, 'output.height': 48})
print('module:', texsim.__file__, r.report['fragments'], 'fragments', r.image.shape)
assert r.image.shape == (48, 64, 3) and r.report['fragments'] > 0
"
}

deb_test() {
  step cpack -G DEB -B "$tmp/deb" --config "$build/CPackConfig.cmake" > "$tmp/cpack.log"
  local deb
  deb=$(ls "$tmp"/deb/texsim_*.deb)
  dpkg-deb -I "$deb" | sed -n '/Package:/,$p'
  dpkg-deb -c "$deb" > "$tmp/contents"
  local want="./usr/bin/texsim ./usr/share/man/man1/texsim.1 ./usr/lib/cmake/texsim/texsimConfig.cmake
    ./usr/share/texsim/scenes/cube.toml"
  [ "$with_python" = python ] && want+=" ./usr/lib/python3/dist-packages/texsim"
  for f in $want; do
    grep -q " $f" "$tmp/contents" || { echo "test-install: $f not in $deb"; exit 1; }
  done
  dpkg-deb -f "$deb" Depends | grep -q libopenimageio || {
    echo "test-install: Depends lacks the shared libraries' packages"; exit 1; }
  # The package's files run where they are unpacked (not installed into this machine's /usr).
  dpkg-deb -x "$deb" "$tmp/root"
  step "$tmp/root/usr/bin/texsim" run "$tmp/root/usr/share/texsim/scenes/cube.toml" --functional \
    --set output.width=64 --set output.height=48 --out "$tmp/deb-run"
  if [ "$with_python" = python ]; then
    step env PYTHONPATH="$tmp/root/usr/lib/python3/dist-packages" "$python" -c "
import texsim
assert texsim.__file__.startswith('$tmp/root/'), texsim.__file__
r = texsim.run('$tmp/root/usr/share/texsim/scenes/cube.toml', functional=True,
               overrides={'output.width': 64, 'output.height': 48})
assert r.image.shape == (48, 64, 3)
"
  fi
  echo "test-install: $(basename "$deb"), $(wc -l < "$tmp/contents") entries"
}

case $mode in
  prefix) prefix_test ;;
  deb) deb_test ;;
  *) echo "usage: $0 prefix|deb BUILD_DIR"; exit 2 ;;
esac

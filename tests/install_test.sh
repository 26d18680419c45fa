#!/usr/bin/env bash
# CTest install_renders_from_another_directory: `cmake --install` into a fresh prefix, then the
# installed binary, run from an unrelated directory, renders the installed Cornell box; its --version
# names the prefix's own OpenImageDenoise where the build tree has one (scripts/setup.sh --oidn),
# and then a --denoise render works from the installed copy alone.
# Usage: tests/install_test.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$1 work=$2
rm -rf "$work"
mkdir -p "$work/prefix" "$work/elsewhere"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
bin="$work/prefix/bin/bundlepath"
scene="$work/prefix/share/bundlepath/scenes/cornell-box.gltf"
[ -x "$bin" ] || { echo "install: no executable $bin" >&2; exit 1; }
[ -f "$scene" ] || { echo "install: no $scene" >&2; exit 1; }
[ -f "$work/prefix/share/doc/bundlepath/LICENSE" ] || { echo "install: no LICENSE" >&2; exit 1; }
cd "$work/elsewhere"
export BUNDLEPATH_CACHE_DIR="$work/kernels" POCL_CACHE_DIR="$work/pocl"
"$bin" --version | tee version.txt
options=(--width 32 --height 32 --spp 4 --mode pt)
if [ -f "$(dirname "$0")/../.deps/oidn/lib/libOpenImageDenoise.so.2" ]; then
  grep -q -- "--denoise: OpenImageDenoise .*$work/prefix/lib/bundlepath/oidn/" version.txt ||
    { echo "install: the installed binary does not find the installed OpenImageDenoise" >&2; exit 1; }
  options+=(--denoise)
elif [ "${BUNDLEPATH_TEST_REQUIRE_OIDN:-0}" = 1 ]; then
  echo "install: BUNDLEPATH_TEST_REQUIRE_OIDN is set but .deps/oidn is missing (bash scripts/setup.sh --oidn)" >&2
  exit 1
fi
"$bin" render "$scene" "${options[@]}" --out img/cornell
[ -s img/cornell.exr ] && [ -s img/cornell.png ] || { echo "install: the render wrote no image" >&2; exit 1; }
echo "install: the installed binary rendered from $PWD (${options[*]})"

#!/usr/bin/env bash
# The README's first command: installs what is missing (Debian 12 packages, and OpenImageDenoise for
# --denoise), builds (Release) and renders the default scene to out/cornell-box.exr and
# out/cornell-box.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --oidn
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$(nproc)"
build/bundlepath render scenes/cornell-box.gltf "$@"

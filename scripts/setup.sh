#!/usr/bin/env bash
# Installs what bundlepath needs from Debian 12 packages; installs nothing that is already there.
# Idempotent: run it as often as you like (as root, or with sudo available).
# --fuzz adds what the libFuzzer target needs (clang and its runtime libraries; scripts/test.sh and
# scripts/fuzz.sh ask for it); other arguments are extra package names to install too.
set -euo pipefail

fuzz_packages=(clang-14 libclang-rt-14-dev)
extra=()
for arg in "$@"; do
  if [ "$arg" = "--fuzz" ]; then extra+=("${fuzz_packages[@]}"); else extra+=("$arg"); fi
done

packages=(
  build-essential cmake pkg-config
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libglm-dev libopenexr-dev libtinygltf-dev nlohmann-json3-dev libstb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin
  ${extra[@]+"${extra[@]}"}
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# Installs what bundlepath needs from Debian 12 packages; installs nothing that is already there.
# Idempotent: run it as often as you like (as root, or with sudo available).
# --fuzz adds what the libFuzzer target needs (clang and its runtime libraries; scripts/test.sh and
# scripts/fuzz.sh ask for it); --oidn adds OpenImageDenoise for `render --denoise` (below); other
# arguments are extra package names to install too.
set -euo pipefail
cd "$(dirname "$0")/.."

fuzz_packages=(clang-14 libclang-rt-14-dev)
extra=()
oidn=0
for arg in "$@"; do
  case "$arg" in
    --fuzz) extra+=("${fuzz_packages[@]}") ;;
    --oidn) oidn=1 ;;
    *) extra+=("$arg") ;;
  esac
done
# OpenImageDenoise: Debian 12 has no package, so the official 2.5.1 runtime comes from PyPI's pyoidn
# wheel (which pip only downloads: nothing is installed into Python). Its library, CPU device and TBB
# go to .deps/oidn/lib, where the build looks for it (CMakeLists.txt); python3 and pip from Debian
# where missing.
if [ "$oidn" -eq 1 ]; then
  command -v python3 >/dev/null 2>&1 || extra+=(python3)
  python3 -m pip --version >/dev/null 2>&1 || extra+=(python3-pip)
fi

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
else
  echo "setup: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

oidn_dir=.deps/oidn
if [ "$oidn" -eq 1 ] && [ ! -e "$oidn_dir/lib/libOpenImageDenoise.so.2" ]; then
  echo "setup: fetching OpenImageDenoise 2.5.1 (PyPI pyoidn) into $oidn_dir"
  wheels=$(mktemp -d)
  trap 'rm -rf "$wheels"' EXIT
  python3 -m pip download --quiet --no-deps --only-binary=:all: --platform manylinux2014_x86_64 \
    --python-version 3.11 -d "$wheels" pyoidn==2.5.1.0
  rm -rf "$oidn_dir.tmp"
  python3 - "$wheels"/pyoidn-*.whl "$oidn_dir.tmp" <<'PY'
import os, sys, zipfile
wheel, out = sys.argv[1], sys.argv[2]
# The core, its CPU device and TBB (the GPU devices' libraries are not needed), and the licences.
wanted = ("libOpenImageDenoise.so.2", "libOpenImageDenoise_core.so.2.5.1",
          "libOpenImageDenoise_device_cpu.so.2.5.1", "libtbb.so.12")
with zipfile.ZipFile(wheel) as z:
    for info in z.infolist():
        name = os.path.basename(info.filename)
        if info.filename.startswith("pyoidn/oidn/lib/") and name in wanted:
            target = os.path.join(out, "lib", name)
        elif ".dist-info/licenses/" in info.filename and not info.is_dir():
            target = os.path.join(out, "licenses", info.filename.split(".dist-info/licenses/", 1)[1])
        else:
            continue
        os.makedirs(os.path.dirname(target), exist_ok=True)
        with z.open(info) as src, open(target, "wb") as dst:
            dst.write(src.read())
        os.chmod(target, 0o755 if "/lib/" in target else 0o644)
missing = [w for w in wanted if not os.path.exists(os.path.join(out, "lib", w))]
if missing:
    sys.exit("setup: the pyoidn wheel lacks " + ", ".join(missing))
PY
  mv "$oidn_dir.tmp" "$oidn_dir"
  echo "setup: OpenImageDenoise is in $oidn_dir (bundlepath looks there first)"
fi

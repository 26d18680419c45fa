#!/usr/bin/env bash
# Installs the peers of bench/peers/run.sh (issue 29) in a Python 3.11 venv of their own:
# Blender Cycles 5.0 as PyPI `bpy==5.0.1` and LuxCoreRender 2.11 as PyPI `pyluxcore`, plus numpy
# and OpenEXR for the comparisons. A few hundred MB; not part of the test command (CI never renders
# the peers). Idempotent: a venv that already imports both is left as it is.
#
#   bash bench/peers/setup.sh [VENV]        (default: bench-out/peers-venv, git-ignored)
#
# Prints the venv's path on its last line. Needs python3.11 (Debian bookworm's python3) with venv.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
venv=${1:-${PEERS_VENV:-$root/bench-out/peers-venv}}
py=${PEERS_PYTHON:-}
if [ -z "$py" ]; then
  for c in /usr/bin/python3.11 python3.11; do
    if command -v "$c" > /dev/null; then py=$(command -v "$c"); break; fi
  done
fi
if [ -z "$py" ]; then
  echo "setup.sh: python3.11 missing (bpy 5.0.1 is built for CPython 3.11 only); apt-get install python3.11-venv" >&2
  exit 2
fi
check='import bpy, pyluxcore, numpy, OpenEXR'
if [ -x "$venv/bin/python" ] && OCL_ICD_VENDORS=/nonexistent "$venv/bin/python" -c "$check" 2> /dev/null; then
  echo "setup.sh: $venv already has bpy, pyluxcore, numpy and OpenEXR" >&2
  echo "$venv"
  exit 0
fi
if [ ! -x "$venv/bin/python" ]; then
  "$py" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --upgrade pip > /dev/null
"$venv/bin/python" -m pip install 'bpy==5.0.1' pyluxcore numpy OpenEXR
OCL_ICD_VENDORS=/nonexistent "$venv/bin/python" - <<'PY'
import bpy, pyluxcore
print("bpy", bpy.app.version_string)
pyluxcore.Init()
print("pyluxcore", pyluxcore.Version())
PY
echo "$venv"

#!/usr/bin/env bash
# Installs what halfspace needs beyond the Rust toolchain, idempotently:
#   - libhdf5-dev and pkg-config (Debian/Ubuntu, apt-get) for the HDF5 output and fixtures;
#   - verify/.venv, a Python virtual environment with verify/requirements.txt (numpy, scipy, mpmath,
#     h5py, scikit-fem; pinned), which regenerates and checks the reference fixtures.
# Safe to run again: it installs only what is missing.
set -euo pipefail

need=()
command -v pkg-config >/dev/null 2>&1 || need+=(pkg-config)
if ! pkg-config --exists hdf5 2>/dev/null && [ ! -e /usr/include/hdf5/serial/hdf5.h ]; then
  need+=(libhdf5-dev)
fi

if ((${#need[@]})); then
  if ! command -v apt-get >/dev/null 2>&1; then
    echo "bootstrap: please install ${need[*]} (HDF5 development files and pkg-config)" >&2
    exit 1
  fi
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "bootstrap: installing ${need[*]}" >&2
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${need[@]}" >/dev/null
fi
echo "bootstrap: system dependencies present" >&2

here="$(cd "$(dirname "$0")" && pwd)"
venv="$here/verify/.venv"
stamp="$venv/.requirements.sha256"
want="$(sha256sum "$here/verify/requirements.txt" | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
  python=python3
  command -v python3.11 >/dev/null 2>&1 && python=python3.11
  if ! "$python" -m venv "$venv" 2>/dev/null; then
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-venv >/dev/null
    "$python" -m venv "$venv"
  fi
  echo "bootstrap: installing verify/requirements.txt into verify/.venv" >&2
  "$venv/bin/pip" install -q --disable-pip-version-check -r "$here/verify/requirements.txt"
  echo "$want" > "$stamp"
fi
echo "bootstrap: verify/.venv ready" >&2

#!/usr/bin/env bash
# Installs what halfspace needs beyond the Rust toolchain, idempotently:
#   - libhdf5-dev and pkg-config (Debian/Ubuntu, apt-get) for the HDF5 output and fixtures.
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

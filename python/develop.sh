#!/usr/bin/env bash
# Builds the Python package `halfspace` (release) into verify/.venv with maturin; ./bootstrap.sh
# installs maturin and pytest there. The extension's Cargo target is python/target.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
venv="$(cd "$here/.." && pwd)/verify/.venv"
export VIRTUAL_ENV="$venv" PYO3_PYTHON="$venv/bin/python"
cd "$here"
"$venv/bin/maturin" develop --release --locked -q

#!/usr/bin/env bash
# Installs Sylva's Debian dependencies (if missing), configures and builds into build/.
# Usage: cmake/build.sh [extra cmake configure arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
bash cmake/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build --parallel "$(nproc)"

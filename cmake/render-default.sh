#!/usr/bin/env bash
# One command for a new user: install, build, render the built-in default scene.
# Writes out/default.exr (rgb + nir bands, variance and AOV layers) and out/default.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash cmake/build.sh
mkdir -p out
./build/app/sylva render -o out/default.exr --png out/default.png "$@"

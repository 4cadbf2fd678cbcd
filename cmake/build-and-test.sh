#!/usr/bin/env bash
# One command for CI and developers: install, build (warnings are errors), run every test.
set -euo pipefail
cd "$(dirname "$0")/.."
bash cmake/build.sh -DSYLVA_WERROR=ON
ctest --test-dir build --output-on-failure --parallel "$(nproc)" --timeout 600

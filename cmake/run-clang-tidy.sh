#!/usr/bin/env bash
# Runs clang-tidy (the repository's .clang-tidy) on the production sources, or on the files given:
#   cmake/run-clang-tidy.sh                 # every .cpp of core geometry render scenes pipeline compare app denoise sensor python
#   cmake/run-clang-tidy.sh render/film.cpp # just these
# Uses per-file compile commands from a configure-only tree (build-tidy/, without unity batches).
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-tidy >/dev/null || { echo "run-clang-tidy: install clang-tidy (apt-get install clang-tidy)" >&2; exit 2; }
cmake -S . -B build-tidy -G Ninja -DCMAKE_BUILD_TYPE=Release -DSYLVA_UNITY_BUILD=OFF -DSYLVA_BUILD_BENCH=OFF \
      -DSYLVA_BUILD_TESTS=OFF >/dev/null
if (($#)); then
  files=("$@")
else
  mapfile -t files < <(find core geometry render scenes pipeline compare app denoise sensor python -name '*.cpp' 2>/dev/null | sort)
fi
# python/ is configured only where pybind11 is installed (cmake/install-deps.sh installs it).
if [[ ! -d build-tidy/python ]]; then
  mapfile -t files < <(printf '%s\n' "${files[@]}" | grep -v '^python/')
fi
printf '%s\0' "${files[@]}" | xargs -0 -P "$(nproc)" -n 4 clang-tidy -p build-tidy --quiet 2>/dev/null
echo "run-clang-tidy: ${#files[@]} files clean"

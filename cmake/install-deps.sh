#!/usr/bin/env bash
# Installs Sylva's build and test dependencies from Debian packages.
# Idempotent: does nothing (and prints nothing) when every package is present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config ninja-build clang-format clang-tidy ccache
  libembree-dev libtbb-dev libglm-dev
  libopenimageio-dev libopenexr-dev libpng-dev python3-imath libopencolorio-dev
  libtomlplusplus-dev libpugixml-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenmpi-dev openmpi-bin  # sylva-mpi (optional at build time; CMake skips it without MPI)
  slurm-wlm munge             # tests/slurm: a single-node cluster started in a temp dir (skipped if absent)
  pybind11-dev python3-pybind11 python3-dev python3-numpy python3-pytest python3-matplotlib  # `import sylva` (python/)
  chromium                    # tests/compare/test_report_browser.cpp: the HTML report in a browser (skipped if absent)
)
for option in "$@"; do
  case $option in
    --bench) packages+=(embree-tools) ;;                # bench/compare_embree.sh
    --fuzz) packages+=(clang libclang-rt-14-dev) ;;     # bench/fuzz.sh: libFuzzer, ASan, UBSan
    *) echo "install-deps: unknown option $option (expected --bench or --fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
((${#missing[@]} == 0)) && exit 0

echo "install-deps: installing ${missing[*]}" >&2
SUDO=""
[[ $(id -u) -ne 0 ]] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq >/dev/null
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null

#!/usr/bin/env bash
# Issue 47's calibration of `sylva compare` (docs/compare.md, "Calibration"): false alarms over
# pairs of independent seeds on three golden scenes, and the detection power of local faults at 64
# and 256 spp on the default forest and on golden scenes. Long: run it by hand, not in the test
# command. At nice 19; table rows in OUT/false_alarms.md and OUT/power.md, one line per comparison
# in OUT/*.log.
#
#   bash bench/golden_calibration.sh [BUILD_DIR] [OUT_DIR]      (PAIRS=200 TRIALS=10 FOREST_TRIALS=5)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-/tmp/sylva-calibration}
tool=$build/bench/sylva_golden_calibration
pairs=${PAIRS:-200}
trials=${TRIALS:-10}
forest_trials=${FOREST_TRIALS:-5}
[[ -x $tool ]] || { echo "golden_calibration: build $tool first (ninja -C $build sylva_golden_calibration)" >&2; exit 2; }
mkdir -p "$out"
run() { nice -n 19 "$tool" "$@"; }

echo "| scene | local tests | spp test vs ref | pairs | fail (alpha 0.001) | fail (alpha 0.05) | pixel share fails |" >"$out/false_alarms.md"
echo "| --- | --- | --- | --- | --- | --- | --- |" >>"$out/false_alarms.md"
for scene in ground_sky instancing tree_aspen; do
  run false-alarms "golden/scenes/$scene.toml" "$pairs" 256 64 >>"$out/false_alarms.md" 2>"$out/false_alarms_$scene.log"
done

echo "| fault | scene | spp | detected | median strongest z | detected by |" >"$out/power.md"
echo "| --- | --- | --- | --- | --- | --- |" >>"$out/power.md"
# Faults are separated by '|' (a set: override may hold commas).
run power data/examples/default.toml 'cab45-all|cab45-oak|cab40-oak|bark+5%|nir-band|horizon+3%' "$forest_trials" 1024 64,256 \
  >>"$out/power.md" 2>"$out/power_forest.log"
run power golden/scenes/tree_aspen.toml 'shadow-alpha|nir-band|horizon+3%|none' "$trials" 4096 64,256 \
  >>"$out/power.md" 2>"$out/power_aspen.log"
run power golden/scenes/ground_sky.toml 'sky+3%|horizon+3%' "$trials" 4096 64,256 >>"$out/power.md" 2>"$out/power_sky.log"
cat "$out/false_alarms.md" "$out/power.md"

#!/usr/bin/env bash
# Peak memory over many small study frames (docs/studies.md, "Cost and memory"): a grid of
# FRAMES (default 400) tiny frames of data/examples/targets.toml (43 aspens, two vehicles) varying
# the sun and the camera, with the study's per-frame progress lines kept. Prints the max RSS after
# the first 10 frames and at the end, and the frames per hour.
#   bash bench/study_memory.sh [BUILD_DIR] [FRAMES] [RES]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build}"
frames="${2:-400}"
res="${3:-32x24}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
w="${res%x*}"; h="${res#*x}"
n=$(( (frames + 19) / 20 ))
elevations=$(python3 -c "print(', '.join(str(10 + 60 * i / 19) for i in range(20)))")
aspects=$(python3 -c "print(', '.join(str(360 * i / $n) for i in range($n)))")
cat > "$work/study.toml" <<STUDY
[study]
scene = "$root/data/examples/targets.toml"
output = "out"
set = ["render.width=$w", "render.height=$h", "render.spp=1"]
[[factors]]
name = "aspect"
values = [$aspects]
[[factors]]
name = "sun_elevation"
set = "sun.elevation"
values = [$elevations]
[camera_orbit]
target = "camouflaged vehicle"
range = 40
aspect = "aspect"
elevation = 5
STUDY
start=$(date +%s.%N)
"$build/app/sylva" study "$work/study.toml" 2> "$work/progress.txt"
end=$(date +%s.%N)
grep -E "^study: 10/" "$work/progress.txt" | tail -1
tail -2 "$work/progress.txt"
python3 -c "print(f'{$frames * 3600 / ($end - $start):.0f} frames/hour at $res, 1 spp (whole run, loading included)')"

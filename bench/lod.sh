#!/bin/sh
# Level of detail (docs/lod.md) on a forest of about 10^5 trees seen from the ground to the horizon
# (bench/scenes/lod_forest.toml): the scene rendered with [lod] on and off, back to back, each run
# timed by /usr/bin/time -v. Prints one table row per run: scene load and BVH build (from the
# render summary), wall and CPU (user + system) time at 1 spp (time to first pixel: load + build +
# one sample), samples/s of the SPP render, peak RSS and the load average before the run; writes
# OUT_DIR/lod.png and OUT_DIR/full.png (the SPP renders). The machine's load goes into every
# figure but the CPU time: compare runs made back to back.
#
# Usage: bench/lod.sh SYLVA OUT_DIR [SPP]      (SPP default 16; 2 threads)
# ORDER (environment, default "lod full"): the runs in order, e.g. "lod full full lod" to
# interleave them.
set -eu
SYLVA=$(realpath "$1")
OUT=$(mkdir -p "$2" && realpath "$2")
SPP=${3:-16}
REPO=$(cd "$(dirname "$0")/.." && pwd)
SCENE="$REPO/bench/scenes/lod_forest.toml"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cp "$SCENE" "$WORK/lod.toml"
sed 's/^enabled = true/enabled = false/' "$SCENE" > "$WORK/full.toml"

echo "| run | instances | unique triangles | leaf quads | curves | BVH MiB | load s | BVH build s | first pixel s (1 spp wall) | first pixel CPU s | samples/s ($SPP spp) | peak RSS MiB | load avg |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
for RUN in ${ORDER:-lod full}; do
  LOAD1=$(cut -d' ' -f1-3 /proc/loadavg)
  /usr/bin/time -v "$SYLVA" render "$WORK/$RUN.toml" -o "$WORK/${RUN}1.exr" --spp 1 --threads 2 \
    > /dev/null 2> "$WORK/${RUN}1.log"
  /usr/bin/time -v "$SYLVA" render "$WORK/$RUN.toml" -o "$WORK/$RUN.exr" --png "$OUT/$RUN.png" --spp "$SPP" \
    --threads 2 > /dev/null 2> "$WORK/$RUN.log"
  python3 - "$RUN" "$WORK/${RUN}1.log" "$WORK/$RUN.log" "$LOAD1" <<'PY'
import re, sys
run, first, full, load = sys.argv[1:5]
a, b = open(first).read(), open(full).read()
def wall(t):
    m = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", t)
    return (int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3)))
load_s = re.search(r"scene loaded in ([\d.]+) s", b).group(1)
m = re.search(r"scene: (\d+) instances, (\d+) unique triangles \+ (\d+) leaf quads \+ (\d+) curves.*BVH ([\d.]+) MiB in (\d+) ms", b)
sps = re.search(r"samples in ([\d.]+) s render", b).group(1)
samples = re.search(r"(\d+) samples in", b).group(1)
cpu = sum(float(x) for x in re.findall(r"(?:User|System) time \(seconds\): ([\d.]+)", a))
rss = max(int(x) for x in re.findall(r"Maximum resident set size \(kbytes\): (\d+)", a + b)) / 1024
print(f"| {run} | {m.group(1)} | {m.group(2)} | {m.group(3)} | {m.group(4)} | {m.group(5)} | {load_s} | "
      f"{int(m.group(6)) / 1000:.1f} | {wall(a):.1f} | {cpu:.1f} | {int(samples) / float(sps):,.0f} | {rss:.0f} | {load} |")
PY
done

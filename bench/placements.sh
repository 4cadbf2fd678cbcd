#!/bin/sh
# Time to first pixel and peak memory of `sylva render` as the number of placed trees grows:
# N trees from 20 variants (Quaking Aspen and California Black Oak × 10 seeds each, at QUALITY),
# rendered at 32×18 with one sample per pixel, so the wall time is the time to the first pixels
# (scene load, variant generation, BVH build) plus a negligible render. Peak RSS and CPU time
# (user + system) from /usr/bin/time -v, the load average when the row was measured.
#
# PLACEMENT=list (default): a CSV placement list (docs/scene_format.md [[placements]]) of exactly N
# rows over a square stand on a flat plane. PLACEMENT=map: a procedural feature map
# ([vegetation], Weber & Penn §6) over a procedural terrain sized for about N trees (two species
# bits, 300 trees/ha each where set, min_spacing 4 m, 10 variants each; each tree's base snapped to
# the lowest terrain point under its trunk); the row reports the trees actually placed.
#
# Usage: bench/placements.sh SYLVA [N ...]      (default N: 1000 10000 100000 1000000)
# QUALITY (environment, default 0.1) is the species' quality: the variants' size. INSTANCING
# (auto, native or array; default auto) is the scene's [render] instancing.
# Writes its lists and scenes to a temporary directory; prints one table row per N.
set -eu
SYLVA=$(realpath "$1")
shift
COUNTS=${*:-"1000 10000 100000 1000000"}
QUALITY=${QUALITY:-0.1}
PLACEMENT=${PLACEMENT:-list}
INSTANCING=${INSTANCING:-auto}
REPO=$(cd "$(dirname "$0")/.." && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

echo "| placement | trees | scene load s | BVH build s | wall s (first pixel) | CPU s | peak RSS MiB | B/tree | load avg |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
# The render settings, camera and materials both placements share.
common_scene() {
  cat <<TOML
[render]
width = 32
height = 18
spp = 1
bands = ["rgb"]
instancing = "$INSTANCING"
[camera]
position = [0.0, -60.0, 30.0]
target = [0.0, 0.0, 0.0]
[materials.soil]
reflectance = 0.2
[materials.bark]
reflectance = 0.3
[materials.leaf]
type = "leaf"
reflectance = 0.45
transmittance = 0.4
TOML
}

# One species of the feature map: its bit and the shipped species file's name.
map_species() {
  cat <<TOML
[[vegetation.species]]
bit = $1
species = "$REPO/data/species/$2.toml"
bark = "bark"
leaf = "leaf"
quality = $QUALITY
density = 300
min_spacing = 4
variants = 10
scale = [0.8, 1.2]
TOML
}

for N in $COUNTS; do
  if [ "$PLACEMENT" = map ]; then
    # About 0.7 of the area carries one of the two species at 300 trees/ha: 210 trees/ha.
    side=$(awk -v n="$N" 'BEGIN { printf "%.0f", sqrt(n / 210.0 * 10000.0) }')
    common_scene > "$WORK/scene.toml"
    cat >> "$WORK/scene.toml" <<TOML
[terrain]
size = [$side, $side]
resolution = $(awk -v s="$side" 'BEGIN { print s / 256.0 }')
relief = 8
material = "soil"
[vegetation]
feature_resolution = $(awk -v s="$side" 'BEGIN { print s / 1024.0 }')
patch_size = 50
tree_cover = 0.7
grass_cover = 0
seed = 3
TOML
    map_species 0 quaking_aspen >> "$WORK/scene.toml"
    map_species 1 california_black_oak >> "$WORK/scene.toml"
  else
  python3 - "$N" "$WORK/trees.csv" <<'PY'
import math, sys
n, path = int(sys.argv[1]), sys.argv[2]
side = math.sqrt(n) * 6.0  # ~6 m spacing: ~280 trees per hectare
species = ["aspen", "oak"]
state = 1
with open(path, "w") as f:
    f.write("x,y,species,seed,scale,heading\n")
    for i in range(n):
        state = (state * 6364136223846793005 + 1442695040888963407) % 2**64
        u = (state >> 11) / 2**53
        state = (state * 6364136223846793005 + 1442695040888963407) % 2**64
        v = (state >> 11) / 2**53
        f.write(f"{(u - 0.5) * side:.2f},{(v - 0.5) * side:.2f},{species[i % 2]},{1 + (i // 2) % 10},"
                f"{0.8 + 0.4 * u:.3f},{360 * v:.1f}\n")
PY
  common_scene > "$WORK/scene.toml"
  cat >> "$WORK/scene.toml" <<TOML
[[meshes]]
shape = "plane"
size = [1e6, 1e6]
material = "soil"
[[placements]]
file = "trees.csv"
[placements.species.aspen]
species = "$REPO/data/species/quaking_aspen.toml"
bark = "bark"
leaf = "leaf"
quality = $QUALITY
[placements.species.oak]
species = "$REPO/data/species/california_black_oak.toml"
bark = "bark"
leaf = "leaf"
quality = $QUALITY
TOML
  fi
  /usr/bin/time -v "$SYLVA" render "$WORK/scene.toml" -o "$WORK/out.exr" --no-memory-check \
    >"$WORK/stdout" 2>"$WORK/stderr" || { cat "$WORK/stderr"; exit 1; }
  grep "^scene:" "$WORK/stderr" >&2
  wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$WORK/stderr" |
    awk -F: '{ if (NF == 3) print $1 * 3600 + $2 * 60 + $3; else print $1 * 60 + $2 }')
  rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$WORK/stderr")
  load=$(sed -n 's/^scene loaded in \([0-9.]*\) s.*/\1/p' "$WORK/stderr")
  bvh=$(sed -n 's/.*BVH .* MiB in \([0-9.]*\) ms.*/\1/p' "$WORK/stderr" | awk '{ printf "%.2f", $1 / 1000 }')
  cpu=$(sed -n 's/.*User time (seconds): //p; s/.*System time (seconds): //p' "$WORK/stderr" |
    awk '{ s += $1 } END { printf "%.2f", s }')
  trees=$(sed -n 's/^scene: \([0-9]*\) instances.*/\1/p' "$WORK/stderr")
  trees=$((trees - 1))  # the ground plane or the terrain
  avg=$(cut -d' ' -f1 /proc/loadavg)
  echo "| $PLACEMENT | $trees | $load | $bvh | $wall | $cpu | $((rss / 1024)) | $((rss * 1024 / trees)) | $avg |"
done

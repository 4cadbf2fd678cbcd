#!/usr/bin/env bash
# The denoiser's benchmark (bench/README.md, "Denoised stills"): renders a reference and noisy
# stills of a scene, denoises the 16- and 64-spp ones, and prints relMSE and equivalent spp
# overall and per class. Usage:
#   bench/denoise_bench.sh SYLVA METRICS OUTDIR [SCENE.toml] [--res WxH] [--ref-spp N] [--threads N]
#                          [--crops "X,Y,W,H ..."] [--view VIEW]
# SYLVA: the sylva binary; METRICS: build/bench/sylva_denoise_metrics. Existing renders in OUTDIR are
# reused (delete them to render again). The reference uses seed 1000, the noisy renders seed 1.
# --crops: for each window, OUTDIR/crop_X_Y.png shows noisy 16 spp | denoised 16 spp | reference at
# 1:1 through one preview transform (the noisy image's auto exposure, VIEW, default ACES;
# sylva_crop_strip, built beside METRICS).
set -euo pipefail
sylva=$1 metrics=$2 out=$3
shift 3
scene="" res=480x270 ref_spp=2048 threads=0 spps="16 64 256 1024" crops="" view=ACES
while [ $# -gt 0 ]; do
  case $1 in
    --res) res=$2; shift 2 ;;
    --ref-spp) ref_spp=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --spps) spps=$2; shift 2 ;;
    --crops) crops=$2; shift 2 ;;
    --view) view=$2; shift 2 ;;
    *) scene=$1; shift ;;
  esac
done
mkdir -p "$out"
render() {  # render SPP SEED OUT.exr [extra args]
  local spp=$1 seed=$2 exr=$3
  shift 3
  [ -f "$exr" ] && return 0
  echo "render $spp spp -> $exr (load: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
  "$sylva" render $scene --res "$res" --spp "$spp" --seed "$seed" --threads "$threads" -o "$exr" -q "$@" \
    --png "${exr%.exr}.png"
}
render "$ref_spp" 1000 "$out/ref.exr"
for spp in $spps; do render "$spp" 1 "$out/noisy_$spp.exr" --features; done
for spp in 16 64; do
  if [ ! -f "$out/denoised_$spp.exr" ]; then
    echo "denoise $spp spp (load: $(cut -d' ' -f1-3 /proc/loadavg))" >&2
    /usr/bin/time -f "denoise $spp spp: %e s wall, %U s user, %S s sys" \
      "$sylva" denoise "$out/noisy_$spp.exr" -o "$out/denoised_$spp.exr" --png "$out/denoised_$spp.png"
  fi
done
# Class groups from the reference's label sidecar: trees (crowns and trunks), grass, terrain, sky,
# targets.
groups=$(python3 - "$out/ref.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
names = {c["id"]: c["name"] for c in d["classes"]}
trees = sorted({v["class"] for v in d["variants"] if v.get("kind") == "tree"})
targets = sorted({t["class"] for t in d.get("targets", [])})
g = {"crowns": trees, "grass": [2], "terrain": [1], "sky": [0], "targets": targets}
print(";".join(f"{k}=" + ",".join(map(str, v)) for k, v in g.items() if v))
PY
)
echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
images=()
for spp in $spps; do images+=("noisy_$spp=$out/noisy_$spp.exr"); done
for spp in 16 64; do images+=("denoised_$spp=$out/denoised_$spp.exr"); done
"$metrics" "$out/ref.exr" "$groups" "${images[@]}"
for crop in $crops; do
  IFS=, read -r cx cy cw ch <<<"$crop"
  "$(dirname "$metrics")/sylva_crop_strip" "$out/crop_${cx}_${cy}.png" "$cx" "$cy" "$cw" "$ch" auto "$view" \
    "$out/noisy_16.exr" "$out/denoised_16.exr" "$out/ref.exr"
done

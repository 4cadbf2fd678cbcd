#!/usr/bin/env bash
# Efficiency against a previous binary (issue 41; bench/README.md, "Efficiency"): for each case,
# work = relMSE × CPU-seconds of a render against a converged reference, lower is better.
#   relMSE      the mean over pixels of (test − ref)² / (ref² + 10⁻⁴ · mean ref²), averaged over
#               R, G and B (compare/rel_mse.h, through sylva_rel_mse)
#   CPU-seconds the render process's user + system time (/usr/bin/time: load, BVH, render, write)
#   reference   the same scene at --ref-spp (2048) with seed --ref-seed (1000), bands rgb (every
#               case's R, G, B have the same expectation whatever other bands are rendered beside
#               them), rendered once by --ref-sylva and cached in --refs under the scene's content
#               hash, resolution, bands, spp and seed (nothing of the binary: render the cache with a
#               trusted binary, e.g. the old one, which is the default).
# The old and the new binary render every case alternately, round after round (round r uses seed
# r for both), and the table gives per case the medians over the rounds, new/old of the median
# works, and each round's new/old with their median, with the load averages (`uptime`) before and
# after.
#
# Usage: bench/efficiency.sh OLD_SYLVA [NEW_SYLVA] [--rounds R] [--spp N] [--res WxH] [--threads N]
#          [--cases "CASE …"] [--ref-spp N] [--ref-seed S] [--ref-sylva PATH] [--refs DIR]
#          [--rel-mse PATH] [--nice N] [--keep DIR]
# NEW_SYLVA: default build/app/sylva of this checkout. CASE: SCENE[:BANDS], SCENE a file of
# data/examples/ without .toml, or a path; BANDS as --bands takes them (default: the scene's).
# Default cases: default:rgb default:rgb,nir default:rgb,nir,S2A_B4,S2A_B8 forest_closeup hazy_stand.
# --rel-mse: default build/bench/sylva_rel_mse beside NEW_SYLVA (built with the benchmarks).
# --nice: niceness of the timed renders (default 0; references always run at 19). --keep DIR keeps
# the test renders and the raw per-run table (runs.tsv) there.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
old=${1:?usage: bench/efficiency.sh OLD_SYLVA [NEW_SYLVA] [options]}
shift
new=$repo/build/app/sylva
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then
  new=$1
  shift
fi
rounds=3 spp=16 res=160x90 threads=2 ref_spp=2048 ref_seed=1000 ref_sylva=$old nice_level=0 keep=""
cases="default:rgb default:rgb,nir default:rgb,nir,S2A_B4,S2A_B8 forest_closeup hazy_stand"
refs=${SYLVA_BENCH_CACHE:-$HOME/.cache/sylva/efficiency}
rel_mse=""
while [ $# -gt 0 ]; do
  case $1 in
    --rounds) rounds=$2 ;;
    --spp) spp=$2 ;;
    --res) res=$2 ;;
    --threads) threads=$2 ;;
    --cases) cases=$2 ;;
    --ref-spp) ref_spp=$2 ;;
    --ref-seed) ref_seed=$2 ;;
    --ref-sylva) ref_sylva=$2 ;;
    --refs) refs=$2 ;;
    --rel-mse) rel_mse=$2 ;;
    --nice) nice_level=$2 ;;
    --keep) keep=$2 ;;
    *) echo "efficiency.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
old=$(realpath "$old") new=$(realpath "$new") ref_sylva=$(realpath "$ref_sylva")
[ -n "$rel_mse" ] || rel_mse=$(dirname "$(dirname "$new")")/bench/sylva_rel_mse
for tool in "$old" "$new" "$ref_sylva" "$rel_mse" /usr/bin/time; do
  [ -x "$tool" ] || { echo "efficiency.sh: $tool is not an executable (build it first)" >&2; exit 2; }
done
if [ -n "$keep" ]; then
  work=$keep
  mkdir -p "$work"
else
  work=$(mktemp -d /tmp/sylva_efficiency.XXXXXX)
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$refs"
load() { cut -d' ' -f1-3 /proc/loadavg; }

scene_file() {  # scene_file SCENE → the TOML path
  case $1 in
    */* | *.toml) realpath "$1" ;;
    *) echo "$repo/data/examples/$1.toml" ;;
  esac
}

# The cached reference of a scene, rendered when missing (nice 19, atomically: sylva writes the EXR
# through a temporary file).
reference() {
  local file=$1 key out
  key="$(basename "$file" .toml)_$(sha256sum "$file" | cut -c1-12)_${res}_rgb_${ref_spp}spp_seed${ref_seed}"
  out=$refs/$key.exr
  if [ ! -f "$out" ]; then
    echo "reference $key with $ref_sylva (load $(load))" >&2
    nice -n 19 "$ref_sylva" render "$file" --res "$res" --spp "$ref_spp" --seed "$ref_seed" --bands rgb \
      --threads "$threads" -q -o "$out"
    echo "$ref_sylva $("$ref_sylva" --version 2>/dev/null || true)" \
      "$(git -C "$(dirname "$ref_sylva")" describe --always --dirty 2>/dev/null || true)" >"$refs/$key.binary.txt"
  fi
  echo "$out"
}

# One timed render and its figures: "CPU_S REL_MSE".
measure() {  # measure SYLVA FILE BANDS SEED REF OUT
  local sylva=$1 file=$2 bands=$3 seed=$4 ref=$5 out=$6
  local args=(render "$file" --res "$res" --spp "$spp" --seed "$seed" --threads "$threads" -q -o "$out")
  [ -n "$bands" ] && args+=(--bands "$bands")
  nice -n "$nice_level" /usr/bin/time -f "%U %S" -o "$out.time" "$sylva" "${args[@]}"
  local cpu
  cpu=$(awk 'END { printf "%.3f", $1 + $2 }' "$out.time")
  echo "$cpu $("$rel_mse" "$out" "$ref")"
}

echo "# efficiency: old $old, new $new; $res, $spp spp, $threads threads, $rounds rounds; references $ref_spp spp seed $ref_seed in $refs"
echo "# uptime before: $(uptime)"
declare -A ref_of
for c in $cases; do
  file=$(scene_file "${c%%:*}")
  [ -f "$file" ] || { echo "efficiency.sh: no scene $file" >&2; exit 2; }
  ref_of[$c]=$(reference "$file")
done
runs=$work/runs.tsv
printf 'round\tcase\tbinary\tcpu_s\trel_mse\twork\tload1\n' >"$runs"
for ((r = 1; r <= rounds; ++r)); do
  for c in $cases; do
    file=$(scene_file "${c%%:*}")
    bands=""
    [ "$c" != "${c#*:}" ] && bands=${c#*:}
    for which in old new; do
      sylva=$old
      [ $which = new ] && sylva=$new
      l=$(load)
      figures=$(measure "$sylva" "$file" "$bands" "$r" "${ref_of[$c]}" "$work/${c//[:,\/]/_}_${which}_$r.exr")
      read -r cpu rel <<<"$figures"
      work_value=$(awk -v a="$cpu" -v b="$rel" 'BEGIN { printf "%.4g", a * b }')
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$r" "$c" "$which" "$cpu" "$rel" "$work_value" "${l%% *}" >>"$runs"
      echo "round $r $c $which: $cpu CPU-s, relMSE $rel, work $work_value (load $l)" >&2
      [ -n "$keep" ] || rm -f "$work/${c//[:,\/]/_}_${which}_$r".*
    done
  done
done
echo "# uptime after: $(uptime)"
# shellcheck disable=SC2086  # one argument per case
python3 - "$runs" $cases <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
print("| case | old relMSE | old CPU s | old work | new relMSE | new CPU s | new work | new/old: medians | new/old: rounds (median) |")
print("|---|---|---|---|---|---|---|---|---|")
for case in sys.argv[2:]:
    runs = {w: [x for x in rows if x["case"] == case and x["binary"] == w] for w in ("old", "new")}
    o, n = ([statistics.median(float(x[k]) for x in runs[w]) for k in ("rel_mse", "cpu_s", "work")] for w in ("old", "new"))
    # Paired by round (same seed, back to back): the median of the rounds' ratios.
    ratios = [float(b["work"]) / float(a["work"]) for a, b in zip(runs["old"], runs["new"])]
    rounds = " ".join(f"{r:.2f}" for r in ratios)
    print(f"| {case.replace(':', ' ')} | {o[0]:.4g} | {o[1]:.2f} | {o[2]:.4g} | {n[0]:.4g} | {n[1]:.2f} | {n[2]:.4g} "
          f"| {n[2] / o[2]:.3f} | {rounds} (**{statistics.median(ratios):.3f}**) |")
PY

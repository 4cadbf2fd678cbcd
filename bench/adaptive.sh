#!/usr/bin/env bash
# Adaptive sampling against uniform sampling (issue 41's goal: "a 2 % median relative error on
# canopy pixels reached at least 2× sooner than uniform sampling with the same sampler";
# bench/README.md, "Adaptive sampling against uniform").
#
# The built-in default forest, bands rgb, rendered R times (seeds 1..R) in each configuration:
# uniform at each of --uniform-spp, and adaptive (--noise-threshold T --spp MAX). No converged
# reference is affordable at 2 %, so each configuration's error is measured from its own replicas
# (bench/replica_error.cpp): per pixel and channel the unbiased variance across the R replicas over
# the squared mean across them, the pixel's relative error the root of its mean over R, G, B, and the
# figure the median of that over canopy pixels (`id.class` of a tree species, from the sidecar
# JSON). The same estimator is applied to both methods.
#   uniform  error × √spp is fitted on the largest --uniform-spp (the others check the 1/√spp
#            law); the uniform spp and CPU time to reach adaptive's achieved error follow.
#   adaptive its CPU time and achieved error, measured.
#   ratio    uniform's CPU time at adaptive's error / adaptive's, for the render loop (sylva's
#            summary, CPU-s) and for the process (/usr/bin/time user + system: scene load and BVH
#            too, a fixed cost that does not shrink with the resolution).
#
# Usage: bench/adaptive.sh [SYLVA] [--res WxH] [--replicas R] [--uniform-spp "64 256"]
#          [--threshold T] [--max-spp N] [--adaptive-args "ARGS"] [--threads N] [--nice N] [--keep DIR]
#          [--tool PATH]
# SYLVA: default build/app/sylva of this checkout; --tool: default bench/sylva_replica_error beside
# it. --adaptive-args: more options of the adaptive renders, e.g. "--set render.pilot_spp=64" or
# "--noise-channels G". Defaults: 96x54, 4 replicas, uniform 64 and 256 spp, T = 0.05, MAX = 8192, 2 threads, nice 19.
# --keep DIR keeps the renders (and reuses those already there: a rerun only analyses), runs.tsv
# (every render's CPU seconds and load) and spp.png, the spp map of replica 1 (log2 grey scale,
# white = MAX).
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
sylva=$repo/build/app/sylva
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then
  sylva=$1
  shift
fi
res=96x54 replicas=4 uniform_spp="64 256" threshold=0.05 max_spp=8192 threads=2 nice_level=19 keep="" tool=""
adaptive_args=""
while [ $# -gt 0 ]; do
  case $1 in
    --res) res=$2 ;;
    --replicas) replicas=$2 ;;
    --uniform-spp) uniform_spp=$2 ;;
    --threshold) threshold=$2 ;;
    --max-spp) max_spp=$2 ;;
    --adaptive-args) adaptive_args=$2 ;;
    --threads) threads=$2 ;;
    --nice) nice_level=$2 ;;
    --keep) keep=$2 ;;
    --tool) tool=$2 ;;
    *) echo "adaptive.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
sylva=$(realpath "$sylva")
[ -n "$tool" ] || tool=$(dirname "$(dirname "$sylva")")/bench/sylva_replica_error
for t in "$sylva" "$tool" /usr/bin/time; do
  [ -x "$t" ] || { echo "adaptive.sh: $t is not an executable (build it first)" >&2; exit 2; }
done
[ "$replicas" -ge 2 ] || { echo "adaptive.sh: --replicas must be at least 2" >&2; exit 2; }
if [ -n "$keep" ]; then
  work=$keep
  mkdir -p "$work"
else
  work=$(mktemp -d /tmp/sylva_adaptive.XXXXXX)
  trap 'rm -rf "$work"' EXIT
fi
load() { cut -d' ' -f1-3 /proc/loadavg; }

# One render (skipped when --keep already holds it): NAME SEED ARGS…; its figures go to NAME.cpu as
# "PROCESS_CPU_S RENDER_CPU_S LOAD1".
render() {
  local name=$1 seed=$2
  shift 2
  [ -f "$work/$name.exr" ] && [ -f "$work/$name.cpu" ] && return 0
  local l
  l=$(load)
  nice -n "$nice_level" /usr/bin/time -f "%U %S" -o "$work/$name.time" "$sylva" render --res "$res" --bands rgb \
    --threads "$threads" --seed "$seed" -o "$work/$name.exr" "$@" 2>"$work/$name.log"
  local render_cpu
  render_cpu=$(sed -n 's/.*(\([0-9.]*\) CPU-s.*/\1/p' "$work/$name.log" | tail -1)
  awk -v r="$render_cpu" -v l="${l%% *}" 'END { printf "%.3f %s %s\n", $1 + $2, r, l }' "$work/$name.time" \
    >"$work/$name.cpu"
  echo "$name: $(cat "$work/$name.cpu") (process CPU-s, render CPU-s, load before)" >&2
}

echo "# adaptive: $sylva; default forest, $res, rgb, $threads threads, nice $nice_level, $replicas replicas;" \
  "uniform $uniform_spp spp; adaptive --noise-threshold $threshold --spp $max_spp $adaptive_args"
echo "# uptime before: $(uptime)"
for ((r = 1; r <= replicas; ++r)); do
  for n in $uniform_spp; do render "u${n}_$r" "$r" --spp "$n"; done
  # shellcheck disable=SC2086  # the extra options, split into words
  render "a_$r" "$r" --spp "$max_spp" --noise-threshold "$threshold" $adaptive_args
done
echo "# uptime after: $(uptime)"

# Canopy: the classes of the trees (the sidecar's variants of kind "tree").
classes=$(python3 -c 'import json, sys
print(",".join(sorted({str(v["class"]) for v in json.load(open(sys.argv[1]))["variants"] if v["kind"] == "tree"})))' \
  "$work/a_1.json")
runs=$work/runs.tsv
printf 'config\tprocess_cpu_s\trender_cpu_s\tload1\tmedian_canopy\tp25_canopy\tp75_canopy\tmedian_all\tmedian_canopy_var\tmean_spp_canopy\tmean_spp_all\tat_max_canopy\n' >"$runs"
for config in $(for n in $uniform_spp; do echo "u$n"; done) a; do
  files=()
  for ((r = 1; r <= replicas; ++r)); do files+=("$work/${config}_$r.exr"); done
  png=()
  [ "$config" = a ] && png=(--spp-png "$work/spp.png" --scale 4)
  canopy=$("$tool" --classes "$classes" "${png[@]}" "${files[@]}")
  all=$("$tool" "${files[@]}")
  field() { awk -v k="$1" '$1 == k { print $2 }' <<<"$2"; }
  cpu=$(for ((r = 1; r <= replicas; ++r)); do cat "$work/${config}_$r.cpu"; done)
  med() { awk -v c="$1" '{ print $c }' <<<"$cpu" | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$config" "$(med 1)" "$(med 2)" "$(med 3)" \
    "$(field median "$canopy")" "$(field p25 "$canopy")" "$(field p75 "$canopy")" "$(field median "$all")" "$(field median_var "$canopy")" \
    "$(field mean_spp "$canopy")" "$(field mean_spp "$all")" "$(field at_max_spp "$canopy")" >>"$runs"
  echo "$config canopy: $(tr '\n' ' ' <<<"$canopy")" >&2
done
python3 - "$runs" "$threshold" <<'PY'
import csv, math, sys
rows = {r["config"]: r for r in csv.DictReader(open(sys.argv[1]), delimiter="\t")}
threshold = float(sys.argv[2])
f = lambda r, k: float(r[k])
uniform = sorted((int(c[1:]), r) for c, r in rows.items() if c != "a")
a = rows["a"]
print("| configuration | spp (canopy mean) | median canopy error (p25–p75) | (from var.*) | median, all pixels "
      "| error·√spp | render CPU-s | process CPU-s |")
print("|---|---|---|---|---|---|---|---|")
def line(name, spp, r):
    print(f"| {name} | {spp} | **{f(r, 'median_canopy'):.4f}** ({f(r, 'p25_canopy'):.3f}–{f(r, 'p75_canopy'):.3f}) "
          f"| {f(r, 'median_canopy_var'):.4f} | {f(r, 'median_all'):.4f} "
          f"| {f(r, 'median_canopy') * math.sqrt(f(r, 'mean_spp_canopy') if r is a else int(spp)):.3f} "
          f"| {f(r, 'render_cpu_s'):.2f} | {f(r, 'process_cpu_s'):.2f} |")
for n, r in uniform:
    line(f"uniform {n} spp", n, r)
line(f"adaptive T = {threshold:g}", f"{f(a, 'mean_spp_canopy'):.0f} (all: {f(a, 'mean_spp_all'):.0f}; "
     f"{100 * f(a, 'at_max_canopy'):.2f} % at the largest)", a)
pts = [(n, f(r, "median_canopy")) for n, r in uniform]
for (n0, e0), (n1, e1) in zip(pts, pts[1:]):
    print(f"\nUniform's median canopy error falls as spp^-{math.log(e0 / e1) / math.log(n1 / n0):.3f} from {n0} to {n1} spp (1/√spp: 0.5).")
# The uniform spp for a median canopy error e: log-log interpolation between the measured spp that
# bracket it, else 1/√spp from the nearest one.
def uniform_spp(e):
    for (n0, e0), (n1, e1) in zip(pts, pts[1:]):
        if e1 <= e <= e0:
            return n0 * (n1 / n0) ** (math.log(e0 / e) / math.log(e0 / e1)), f"interpolated between {n0} and {n1} spp"
    n, en = pts[-1] if e < pts[-1][1] else pts[0]
    return n * (en / e) ** 2, f"extrapolated as 1/√spp from {n} spp"
# Render CPU-s per spp from the largest uniform run; the process's fixed cost (load, BVH, output) =
# process − render CPU-s of the same run.
n, r = uniform[-1]
per_spp = f(r, "render_cpu_s") / n
fixed = f(r, "process_cpu_s") - f(r, "render_cpu_s")
e = f(a, "median_canopy")
n_eq, how = uniform_spp(e)
u_render, u_process = per_spp * n_eq, fixed + per_spp * n_eq
print(f"\nAt adaptive's median canopy error {e:.4f}: uniform needs {n_eq:.0f} spp ({how}), {u_render:.1f} render "
      f"CPU-s ({u_process:.1f} process CPU-s); adaptive took {f(a, 'render_cpu_s'):.1f} ({f(a, 'process_cpu_s'):.1f}).")
print(f"**Ratio uniform / adaptive: {u_render / f(a, 'render_cpu_s'):.2f} (render loop), "
      f"{u_process / f(a, 'process_cpu_s'):.2f} (process).**")
n2, how2 = uniform_spp(0.02)
s = (e / 0.02) ** 2
print(f"Carried to 2 % (uniform {how2}; adaptive's render time × (error / 0.02)²): uniform {per_spp * n2:.0f} render "
      f"CPU-s ({n2:.0f} spp), adaptive {f(a, 'render_cpu_s') * s:.0f}: ratio {per_spp * n2 / (f(a, 'render_cpu_s') * s):.2f}.")
PY

#!/usr/bin/env bash
# Path samples per second of Sylva against Embree's own `pathtracer` tutorial on the same scene.
#
#   bench/compare_embree.sh SYLVA [SCENE.toml] [--res WxH] [--threads N] [--frames N] [--max-path-length N]
#                           [--pathtracer PATH] [--rounds R] [--isa ISA]
#
# SYLVA is a built `sylva` binary (this script builds nothing). Without SCENE the built-in default
# scene is used. The scene is exported with `sylva export --no-materials` to one world-space OBJ
# (leaf quads as two full triangles each, the tutorial's default material everywhere: its filter
# reads an opacity map at the ray's previous hit, not the candidate's, so `map_d` leaf outlines do
# not cut there — bench/README.md) plus the tutorial's camera and light options, then rendered by
#   pathtracer -i scene.obj --size W H --spp 1 --benchmark 4 N --legacy --threads T <camera, lights>
# (4 warm-up frames, N timed frames of one path per pixel; the tutorial's default maximum path
# length is 8, --max-path-length N passes another to it and the same cap to Sylva as --max-depth N,
# so both stop a path after the same number of bounces), and by
#   sylva render SCENE --res WxH --spp N --seed 1 --threads T [--max-depth N]
# (N samples per pixel in one pass: the same number of paths per pixel as the N timed frames).
#
# A "sample" is one camera path in both: for the tutorial, samples/s = W·H·spp·fps with spp = 1
# and fps its BENCHMARK_RENDER_AVG; its BENCHMARK_RENDER_MRAYPS_AVG counts every ray it traces
# (closest-hit and shadow). For Sylva, one sample is one path carrying 4 hero wavelengths; rays/s
# counts closest-hit and shadow rays. Both figures come from the renderers' own clocks (render loop
# only, no scene load, BVH build or image output). Ratio = Sylva samples/s ÷ pathtracer samples/s.
# Reproducible: fixed seed and resolution, an explicit thread count (default 2) for both.
# Embree's kernels: by default each renderer's own choice (the tutorial the processor's widest, Sylva
# AVX2: `sylva render --isa`); --isa ISA (sse2, sse4.2, avx, avx2 or avx512) gives both the same
# cap: the tutorial `--isa ISA --rtcore max_isa=ISA`, Sylva `--isa ISA`.
#
# On a shared machine one run of each can differ by 10 % from the next: --rounds R runs the two
# renderers alternately R times (the export once), prints every run with the 1-minute load average
# before it, and summarises with the median of each figure and of the per-round ratios. With two or
# more rounds it adds, for the rays/s ratio, the geometric mean of the rounds with its standard error
# and a one-sided sign test: how many rounds reached 1.0, and the probability of at least that many
# if each round were as likely below 1.0 as above (the goal's "ratio ≥ 1.0" as a statistical claim).
set -euo pipefail

usage() { sed -n '4,5p' "$0" | sed 's/^# *//' >&2; exit 2; }
[[ $# -ge 1 ]] || usage
sylva=$1
shift
scene=""
res=640x360
threads=2
frames=20
pathtracer=pathtracer
rounds=1
embree_extra=()
sylva_extra=()
while [[ $# -gt 0 ]]; do
  case $1 in
    --res) res=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --frames) frames=$2; shift 2 ;;
    --pathtracer) pathtracer=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    --max-path-length) embree_extra+=(--max-path-length "$2"); sylva_extra+=(--max-depth "$2"); shift 2 ;;
    --isa)
      [[ $2 =~ ^(sse2|sse4\.2|avx|avx2|avx512)$ ]] ||
        { echo "compare_embree: --isa expects sse2, sse4.2, avx, avx2 or avx512, not '$2'" >&2; exit 2; }
      embree_extra+=(--isa "$2" --rtcore "max_isa=$2"); sylva_extra+=(--isa "$2"); shift 2 ;;
    -h|--help) usage ;;
    -*) echo "compare_embree: unknown option $1" >&2; usage ;;
    *) scene=$1; shift ;;
  esac
done
[[ -x $sylva ]] || { echo "compare_embree: $sylva is not an executable (build the sylva target first)" >&2; exit 2; }
command -v "$pathtracer" >/dev/null ||
  { echo "compare_embree: no '$pathtracer' (Debian: embree-tools; cmake/install-deps.sh --bench)" >&2; exit 2; }
[[ $res =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "compare_embree: --res expects WxH, not '$res'" >&2; exit 2; }
width=${BASH_REMATCH[1]}
height=${BASH_REMATCH[2]}
[[ $rounds =~ ^[1-9][0-9]*$ ]] || { echo "compare_embree: --rounds expects a positive integer, not '$rounds'" >&2; exit 2; }

work=$(mktemp -d "${TMPDIR:-/tmp}/sylva-compare.XXXXXX")
trap 'rm -rf "$work"' EXIT

echo "machine: $(nproc) threads, $(lscpu | sed -n 's/^Model name: *//p' | head -1); load average: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "scene: ${scene:-<default scene>}, ${width}x${height}, $threads threads, $frames paths per pixel${embree_extra[*]:+, pathtracer ${embree_extra[*]}}"

# 1. Export: the OBJ, and the camera/light options on stdout. Grass curves are left out of the OBJ
# (export says how many on stderr) but Sylva renders them: then the two renderers trace different
# scenes, and the figures below are not like for like (the default scene's like-for-like twin is
# bench/scenes/forest_no_grass.toml).
read -r -a view < <("$sylva" export ${scene:+"$scene"} --obj "$work/scene.obj" --no-materials --res "$res" -q 2>"$work/export.err")
cat "$work/export.err" >&2
if left_out=$(grep -o '[0-9]* grass blades (curves) left out' "$work/export.err"); then
  echo "NOT LIKE FOR LIKE: the pathtracer's OBJ has no grass ($left_out) and Sylva renders it;" \
    "compare a scene without grass (bench/scenes/forest_no_grass.toml for the default scene)"
fi

# 2. and 3. The tutorial and Sylva, alternately, `rounds` times; one line of figures per round.
load() { cut -d' ' -f1 /proc/loadavg; }
: >"$work/rounds"
for ((r = 1; r <= rounds; ++r)); do
  # The tutorial.
  embree_load=$(load)
  "$pathtracer" -i "$work/scene.obj" "${view[@]}" "${embree_extra[@]}" --spp 1 --benchmark 4 "$frames" --legacy \
    --threads "$threads" >"$work/embree.log" 2>&1 || { cat "$work/embree.log" >&2; exit 1; }
  fps=$(sed -n 's/^BENCHMARK_RENDER_AVG //p' "$work/embree.log")
  mrays=$(sed -n 's/^BENCHMARK_RENDER_MRAYPS_AVG //p' "$work/embree.log")
  [[ -n $fps ]] || { echo "compare_embree: no BENCHMARK_RENDER_AVG in pathtracer output:" >&2; cat "$work/embree.log" >&2; exit 1; }

  # Sylva, same size, same paths per pixel, fixed seed.
  sylva_load=$(load)
  "$sylva" render ${scene:+"$scene"} -o "$work/sylva.exr" --res "$res" --spp "$frames" --seed 1 --threads "$threads" \
    "${sylva_extra[@]}" --checkpoint-minutes 0 >"$work/sylva.log" 2>&1 || { cat "$work/sylva.log" >&2; exit 1; }
  summary=$(grep 'M samples/s' "$work/sylva.log" | tail -1)
  [[ $summary =~ ([0-9.]+)\ M\ samples/s,\ ([0-9.]+)\ M\ rays/s ]] ||
    { echo "compare_embree: no throughput line in sylva output:" >&2; cat "$work/sylva.log" >&2; exit 1; }
  echo "$r $embree_load $fps ${mrays:-nan} $sylva_load ${BASH_REMATCH[1]} ${BASH_REMATCH[2]}" >>"$work/rounds"
done

sort -n "$work/rounds" | awk -v w="$width" -v h="$height" -v n="$rounds" '
  function median(a, k,   i, j, t) {  # of a[1..k], sorted in place
    for (i = 2; i <= k; ++i) for (j = i; j > 1 && a[j - 1] > a[j]; --j) { t = a[j]; a[j] = a[j - 1]; a[j - 1] = t }
    return k % 2 ? a[(k + 1) / 2] : 0.5 * (a[k / 2] + a[k / 2 + 1])
  }
  {
    ems[NR] = w * h * $3 / 1e6; emr[NR] = $4; sms[NR] = $6; smr[NR] = $7
    rs[NR] = sms[NR] / ems[NR]; rr[NR] = smr[NR] / emr[NR]
    if (n > 1) {
      if (NR == 1) printf "%-6s %-6s %12s %12s %-6s %12s %12s %10s %10s\n", "round", "load", "embree Ms/s", "embree Mr/s", "load", "sylva Ms/s", "sylva Mr/s", "ratio s/s", "ratio r/s"
      printf "%-6d %-6s %12.3f %12.3f %-6s %12.3f %12.3f %10.3f %10.3f\n", $1, $2, ems[NR], emr[NR], $5, sms[NR], smr[NR], rs[NR], rr[NR]
    }
  }
  END {
    if (n > 1) printf "median of %d rounds:\n", n
    e_s = median(ems, NR); e_r = median(emr, NR); s_s = median(sms, NR); s_r = median(smr, NR)
    printf "%-22s %12s %12s %12s\n", "", "M samples/s", "M rays/s", "rays/sample"
    printf "%-22s %12.3f %12.3f %12.2f\n", "embree pathtracer", e_s, e_r, e_r / e_s
    printf "%-22s %12.3f %12.3f %12.2f\n", "sylva", s_s, s_r, s_r / s_s
    printf "ratio (sylva / embree pathtracer): samples/s %.3f, rays/s %.3f\n", median(rs, NR), median(rr, NR)
    if (NR > 1) {
      # Geometric mean of the rays/s ratios, its standard error (delta method on the logs).
      s = 0; ss = 0; above = 0
      for (i = 1; i <= NR; ++i) { l = log(rr[i]); s += l; ss += l * l; above += rr[i] >= 1.0 }
      m = s / NR; sd = sqrt((ss - NR * m * m) / (NR - 1))
      # P(at least `above` of NR rounds >= 1.0 | each one a fair coin): the p-value of the sign test.
      pk = 0.5 ^ NR; p = 0
      for (k = 0; k <= NR; ++k) { if (k >= above) p += pk; pk *= (NR - k) / (k + 1) }
      printf "rays/s ratio over %d rounds: geometric mean %.3f (standard error %.3f); %d rounds >= 1.0, sign test p = %.3g\n", NR, exp(m), exp(m) * sd / sqrt(NR), above, p
    }
  }'

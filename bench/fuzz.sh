#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, SYLVA_FUZZ=ON, clang + ASan/UBSan) and runs one of them, or
# all in turn, for SECONDS each; prints executions, coverage and findings per target.
#
#   bench/fuzz.sh TARGET|all SECONDS [WORKDIR]       (SYLVA=build/app/sylva: make seeds with it)
#
# TARGET: scene species obj ply checkpoint exr. WORKDIR (default build-fuzz/runs) keeps, per
# target, the seed corpus (from the repository's own files), the growing corpus, crash/timeout
# artifacts (crashes/) and the log. Fuzzers run one at a time under `nice -n 5`, each with a 30 s
# per-input timeout (120 s for scene, 180 s for species, restarted after a timeout: see below) and a
# 4 GB memory limit.
# A crasher found here belongs in tests/data/fuzz/ with a regression test (docs/robustness.md).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
targets=(scene species obj ply checkpoint exr)
[[ $# -ge 2 ]] || { echo "usage: $0 TARGET|all SECONDS [WORKDIR]  (TARGET: ${targets[*]})" >&2; exit 2; }
what=$1 seconds=$2 work=${3:-$root/build-fuzz/runs}
if [[ $what != all ]]; then
  [[ " ${targets[*]} " == *" $what "* ]] || { echo "unknown target '$what' (expected: ${targets[*]} or all)" >&2; exit 2; }
  targets=("$what")
fi

bash "$root/cmake/install-deps.sh" --fuzz
build=$root/build-fuzz
if [[ ! -f $build/build.ninja ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DSYLVA_FUZZ=ON -DSYLVA_BUILD_TESTS=OFF -DSYLVA_BUILD_BENCH=OFF >/dev/null
fi
# The seeds are made with $SYLVA if set (any build of sylva), else with the fuzz build's own.
sylva=${SYLVA:-$build/app/sylva}
ninja -C "$build" -j2 "${targets[@]/#/fuzz_}" $([[ -n ${SYLVA:-} ]] || echo sylva) >/dev/null
export ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1

# Seed corpora, from the repository's files (and small outputs of sylva made from them).
seeds() {
  local target=$1 dir=$2 tmp
  mkdir -p "$dir"
  case $target in
    scene)
      # Every example and golden scene but the slowest to load (four_species.toml: 9 s under ASan).
      cp "$root"/data/examples/*.toml "$root"/golden/scenes/*.toml "$root"/bench/scenes/*.toml "$dir"/
      rm "$dir"/four_species.toml ;;
    species)
      # First byte: the format, an index into species_file_extensions() (scenes/species.cpp).
      local ext i f
      local exts=(toml xml lsys grammar tmpl)
      for f in "$root"/data/species/* "$root"/tests/data/arbaro/*.xml; do
        ext=${f##*.}
        for i in "${!exts[@]}"; do
          if [[ ${exts[$i]} == "$ext" ]]; then printf "\\x0$i" | cat - "$f" >"$dir/$(basename "$f")"; fi
        done
      done ;;
    obj | ply)
      "$sylva" tree "$root"/data/species/abop_bush.lsys --quality 0.2 --"$target" "$dir/bush.$target"
      "$sylva" tree "$root"/data/species/dogwood.tmpl --quality 0.1 --"$target" "$dir/dogwood.$target" ;;
    checkpoint)
      # Films of partial files (render/chunk.cpp) with the partial header cut off: 8-byte magic,
      # 8-byte length, header text.
      tmp=$(mktemp -d)
      "$sylva" render "$root"/golden/scenes/ground_sun.toml --res 8x6 --spp 2 --chunk 0/1 -q -o "$tmp/a.partial"
      "$sylva" render "$root"/golden/scenes/ground_sun.toml --res 6x4 --spp 4 --chunk 1/2 -q -o "$tmp/b.partial"
      "$sylva" render "$root"/golden/scenes/ground_sun.toml --res 6x4 --spp 2 --chunk 1/2 --split tiles -q -o "$tmp/c.partial"
      for f in "$tmp"/*.partial; do
        python3 - "$f" "$dir/$(basename "$f" .partial).checkpoint" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<Q", data, 8)[0]
open(sys.argv[2], "wb").write(data[16 + n:])
PY
      done
      rm -rf "$tmp" ;;
    exr)
      "$sylva" render "$root"/golden/scenes/ground_sun.toml --res 8x6 --spp 1 -q -o "$dir/small.exr"
      "$sylva" render "$root"/golden/scenes/ground_sun.toml --res 5x3 --spp 1 --bands rgb -q -o "$dir/rgb.exr"
      cp "$root"/golden/ground_sun.exr "$dir"/ ;;
  esac
}

for t in "${targets[@]}"; do
  d=$work/$t
  mkdir -p "$d/corpus" "$d/crashes"
  [[ -d $d/seeds ]] || seeds "$t" "$d/seeds"
  echo "fuzz_$t: ${seconds} s, log $d/log.txt" >&2
  # A species within the stem budget can take a minute to generate under ASan on a busy machine
  # (a six-level willow: 3.5 s of CPU in a release build), and a valid scene growing Hart-Baker
  # trees for 70 years 27 s (years <= 500): slow, not hung. libFuzzer ends a run at its first
  # timeout, so these two targets are restarted (on the grown corpus) after a timeout until SECONDS
  # are used; every timeout-* artifact is then replayed and triaged by hand (slow but valid, or
  # hung: a finding). A crash or out-of-memory ends the run.
  timeout=30 restart=0
  case $t in
    scene) timeout=120 restart=1 ;;
    species) timeout=180 restart=1 ;;
  esac
  : >"$d/log.txt"
  status=0 execs=0 runs=0 start=$SECONDS
  while ((SECONDS - start < seconds)); do
    status=0 runs=$((runs + 1))
    before=$(find "$d/crashes" -type f -name 'timeout-*' | wc -l)
    nice -n 5 "$build/fuzz/fuzz_$t" "$d/corpus" "$d/seeds" -max_total_time=$((seconds - (SECONDS - start))) \
      -timeout="$timeout" -rss_limit_mb=4096 -max_len=65536 -artifact_prefix="$d/crashes/" -print_final_stats=1 \
      >"$d/run.txt" 2>&1 || status=$?
    cat "$d/run.txt" >>"$d/log.txt"
    n=$(grep -E '^stat::number_of_executed_units' "$d/run.txt" | awk '{print $2}' || true)
    [[ -n $n ]] || n=$(grep -E '^#[0-9]+' "$d/run.txt" | tail -n 1 | sed -E 's/^#([0-9]+).*/\1/' || true)
    execs=$((execs + ${n:-0}))
    after=$(find "$d/crashes" -type f -name 'timeout-*' | wc -l)
    ((status != 0 && restart && after > before)) || break
  done
  rm -f "$d/run.txt"
  last=$(grep -E '^#[0-9]+' "$d/log.txt" | tail -n 1 || true)
  crashes=$(find "$d/crashes" -type f \( -name 'crash-*' -o -name 'oom-*' -o -name 'leak-*' \) | wc -l)
  timeouts=$(find "$d/crashes" -type f -name 'timeout-*' | wc -l)
  slow=$(find "$d/crashes" -type f -name 'slow-unit-*' | wc -l)
  printf '%-10s exit %d  %d s in %d run(s)  executions %d  %s  crashes/ooms %d  timeouts %d (triage)  slow units %d\n' \
    "$t" "$status" $((SECONDS - start)) "$runs" "$execs" \
    "$(grep -oE 'cov: [0-9]+ ft: [0-9]+ corp: [0-9]+/[0-9a-zA-Z]+' <<<"$last" || true)" "$crashes" "$timeouts" "$slow"
done

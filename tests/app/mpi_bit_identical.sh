#!/usr/bin/env bash
# sylva-mpi renders equal the single-process render byte for byte: mpirun -n 2 and -n 4, chunks by
# tiles and by samples, and with --denoise (denoised after the merge); a rank that fails makes the
# run fail with a message naming it; a rank that is killed ends the job, and the chunks finished
# before are kept: rendering the missing ones with `sylva render --chunk` and merging gives the
# single render's bytes.
# Usage: mpi_bit_identical.sh SYLVA SYLVA_MPI MPIEXEC
set -euo pipefail
sylva=$1 sylva_mpi=$2 mpiexec=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
objects="$(cd "$(dirname "$0")/../.." && pwd)/data/examples/objects.toml"  # the CLI tests' small scene
common=("$objects" --res 40x24 --spp 6 --threads 1 --quiet)
"$sylva" render -o "$dir/single.exr" --png "$dir/single.png" "${common[@]}"
fail=0
for n in 2 4; do
  for split in tiles samples; do
    out="$dir/mpi_${n}_${split}.exr"
    "$mpiexec" --allow-run-as-root --oversubscribe -n "$n" "$sylva_mpi" -o "$out" --png "$dir/mpi.png" \
      --split "$split" "${common[@]}"
    if cmp -s "$dir/single.exr" "$out" && cmp -s "$dir/single.png" "$dir/mpi.png"; then
      echo "ok: -n $n by $split is byte-identical"
    else
      echo "FAIL: -n $n by $split differs from the single-process render"
      fail=1
    fi
    [[ ! -e "$out.parts" ]] || { echo "FAIL: $out.parts left behind"; fail=1; }
  done
done
# Denoising after the merge: sylva-mpi --denoise equals sylva render --denoise byte for byte.
"$sylva" render -o "$dir/single_dn.exr" --png "$dir/single_dn.png" --denoise "${common[@]}"
for split in tiles samples; do
  "$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$sylva_mpi" -o "$dir/mpi_dn.exr" --png "$dir/mpi_dn.png" \
    --split "$split" --denoise "${common[@]}"
  if cmp -s "$dir/single_dn.exr" "$dir/mpi_dn.exr" && cmp -s "$dir/single_dn.png" "$dir/mpi_dn.png"; then
    echo "ok: --denoise over -n 2 by $split is byte-identical"
  else
    echo "FAIL: --denoise over -n 2 by $split differs from sylva render --denoise"
    fail=1
  fi
done
# A failing rank: an impossible split (more sample chunks than samples) fails on every rank, with a
# message and a non-zero exit, and writes no output.
if "$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$sylva_mpi" -o "$dir/bad.exr" --split samples --chunks 9 \
  "${common[@]}" 2>"$dir/err.txt"; then
  echo "FAIL: an impossible split succeeded"
  fail=1
elif ! grep -q "every chunk needs a sample" "$dir/err.txt" || [[ -e "$dir/bad.exr" ]]; then
  echo "FAIL: no clear message for a failing rank:"
  cat "$dir/err.txt"
  fail=1
else
  echo "ok: a failing rank fails the run with: $(grep -m1 'sylva-mpi' "$dir/err.txt")"
fi
# A killed rank: SIGKILL rank 1 once a few chunks are in OUT.exr.parts/.
big=("$objects" --res 120x96 --spp 64 --threads 1 --quiet)
"$sylva" render -o "$dir/big.exr" "${big[@]}"
"$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$sylva_mpi" -o "$dir/killed.exr" --chunks 48 "${big[@]}" \
  >"$dir/killed.txt" 2>&1 &
mpi_pid=$!
for _ in $(seq 300); do
  (($(find "$dir/killed.exr.parts" -name '*.part' 2>/dev/null | wc -l) >= 4)) && break
  sleep 0.1
done
for p in $(pgrep -f -- "-o $dir/killed.exr"); do
  if tr '\0' '\n' <"/proc/$p/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then kill -9 "$p"; fi
done
if wait "$mpi_pid"; then
  echo "FAIL: the job succeeded although rank 1 was killed"
  fail=1
elif ! grep -q "rank 1" "$dir/killed.txt" || [[ -e "$dir/killed.exr" ]]; then
  echo "FAIL: a killed rank is not named, or an output was written:"
  cat "$dir/killed.txt"
  fail=1
else
  kept=$(find "$dir/killed.exr.parts" -name '*.part' | wc -l)
  for i in $(seq 0 47); do
    part="$dir/killed.exr.parts/chunk.$i.of.48.part"
    [[ -e $part ]] || "$sylva" render -o "$part" --chunk "$i/48" --split tiles "${big[@]}"
  done
  "$sylva" merge "$dir"/killed.exr.parts/*.part -o "$dir/completed.exr" --quiet
  if cmp -s "$dir/big.exr" "$dir/completed.exr"; then
    echo "ok: killed rank 1 ended the job ($(grep -m1 -o 'process rank 1.*' "$dir/killed.txt")); $kept of 48 chunks were kept, and completing them with sylva render --chunk merges to the single render's bytes"
  else
    echo "FAIL: the kept chunks + re-rendered ones differ from the single render"
    fail=1
  fi
fi
exit $fail

#!/usr/bin/env bash
# sylva-mpi renders equal the single-process render byte for byte: mpirun -n 2 and -n 4, chunks by
# tiles and by samples, and a rank that fails makes the run fail with a message naming it.
# Usage: mpi_bit_identical.sh SYLVA SYLVA_MPI MPIEXEC
set -euo pipefail
sylva=$1 sylva_mpi=$2 mpiexec=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
common=(--res 40x24 --spp 6 --threads 1 --quiet)
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
exit $fail

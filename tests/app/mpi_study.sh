#!/usr/bin/env bash
# sylva-mpi --study equals sylva study byte for byte: a tiny 6-frame study (tiny_study.sh) over 2
# and 3 ranks writes the same manifest, frames (EXR, sidecar, PNG, COCO, YOLO, VOC) and study COCO
# as one process; frames are spread over the ranks (at least two render some: which rank takes
# which frame depends on timing, the bytes do not); a run after some frames were lost renders only those
# (the others untouched) and gives the same bytes again.
# Usage: mpi_study.sh SYLVA SYLVA_MPI MPIEXEC
set -euo pipefail
sylva=$1 sylva_mpi=$2 mpiexec=$3
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# shellcheck source=tests/app/tiny_study.sh
source "$(dirname "$0")/tiny_study.sh"
write_tiny_study "$dir"
"$sylva" study "$dir/study.toml" -o "$dir/single" --threads 1 --quiet
fail=0
same() {  # same FOLDER: every file of the single run, byte for byte
  if diff -r "$dir/single" "$1" >/dev/null; then
    echo "ok: $2"
  else
    echo "FAIL: $2"
    diff -r "$dir/single" "$1" | head -5
    fail=1
  fi
}
for n in 2 3; do
  "$mpiexec" --allow-run-as-root --oversubscribe -n "$n" "$sylva_mpi" --study "$dir/study.toml" -o "$dir/mpi$n" \
    --threads 1 2>"$dir/mpi$n.txt"
  same "$dir/mpi$n" "-n $n writes the bytes of one process"
  summary=$(grep "sylva-mpi study:" "$dir/mpi$n.txt")
  echo "  $summary"
  per_rank=$(sed -E 's/.*per rank:([0-9 ]*)\).*/\1/' <<<"$summary")
  busy=$(tr ' ' '\n' <<<"$per_rank" | grep -c '[1-9]' || true)
  if [[ $(wc -w <<<"$per_rank") -ne $n ]] || ((busy < 2)) || ! grep -q " 6 rendered" <<<"$summary"; then
    echo "FAIL: -n $n: the frames were not spread over the ranks: $summary"
    fail=1
  fi
done
# Resume: two frames lost (one whole, one only its annotations) are rendered again, alone.
frames=("$dir"/mpi2/frames/*.exr)
lost=$(basename "${frames[0]}" .exr) half=$(basename "${frames[3]}" .exr)
rm "$dir/mpi2/frames/$lost".* "$dir/mpi2/frames/$half.xml" "$dir/mpi2/coco.json"
before=$(stat -c '%n %Y.%s' "$dir"/mpi2/frames/*.exr | grep -v -e "$lost" -e "$half")
sleep 1
"$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$sylva_mpi" --study "$dir/study.toml" -o "$dir/mpi2" \
  --threads 1 2>"$dir/resume.txt"
same "$dir/mpi2" "a resumed -n 2 run writes the bytes of one process"
grep -q " 2 rendered" "$dir/resume.txt" || { echo "FAIL: the resumed run: $(cat "$dir/resume.txt")"; fail=1; }
if [[ "$before" != "$(stat -c '%n %Y.%s' "$dir"/mpi2/frames/*.exr | grep -v -e "$lost" -e "$half")" ]]; then
  echo "FAIL: the resumed run rendered finished frames again"
  fail=1
fi
exit $fail

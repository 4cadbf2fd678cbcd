#!/usr/bin/env bash
# Submits a split render: an N-task array of chunks, then a merge that runs once all succeeded.
#   scripts/slurm/submit_chunks.sh N OUT.exr [SCENE.toml] [-- render options]
# Environment: SYLVA (binary, default `sylva`), SPLIT (samples|tiles), PNG (preview path),
# SBATCH_ARGS (extra sbatch options, e.g. "--partition=render --cpus-per-task=8").
# Prints the two job ids: ARRAY_ID MERGE_ID.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
n=${1:?N chunks}
out=$(realpath -m "${2:?OUT.exr}")
shift 2
scene=""
if [[ $# -gt 0 && $1 != "--" ]]; then scene=$(realpath "$1"); shift; fi
[[ ${1:-} == "--" ]] && shift
render_args="$*"
export SYLVA="${SYLVA:-sylva}" SPLIT="${SPLIT:-samples}" OUT="$out" SCENE="$scene" RENDER_ARGS="$render_args"
export PNG="${PNG:+$(realpath -m "$PNG")}"
# shellcheck disable=SC2086
array=$(sbatch --parsable ${SBATCH_ARGS:-} --array="0-$((n - 1))" --export=ALL "$here/chunks.sbatch")
# shellcheck disable=SC2086
merge=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok:$array" --kill-on-invalid-dep=yes --export=ALL \
  "$here/merge.sbatch")
echo "$array $merge"

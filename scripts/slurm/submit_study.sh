#!/usr/bin/env bash
# Submits a detection study: an N-task array of shards (study.sbatch), then one job, once all
# succeeded, that renders any frame still missing and writes the study's coco.json.
#   scripts/slurm/submit_study.sh N STUDY.toml [OUT]
# Environment: SYLVA (binary, default `sylva`), STUDY_ARGS (more `sylva study` options),
# SBATCH_ARGS (extra sbatch options, e.g. "--partition=render --cpus-per-task=8").
# Prints the two job ids: ARRAY_ID COLLECT_ID. OUT must be on a file system every node shares.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
n=${1:?N shards}
study=$(realpath "${2:?STUDY.toml}")
out=${3:+$(realpath -m "$3")}
export SYLVA="${SYLVA:-sylva}" STUDY="$study" OUT="$out" STUDY_ARGS="${STUDY_ARGS:-}"
# shellcheck disable=SC2086
array=$(sbatch --parsable ${SBATCH_ARGS:-} --array="0-$((n - 1))" --export=ALL "$here/study.sbatch")
# shellcheck disable=SC2086
collect=$(sbatch --parsable ${SBATCH_ARGS:-} --dependency="afterok:$array" --kill-on-invalid-dep=yes --export=ALL \
  "$here/study.sbatch")
echo "$array $collect"

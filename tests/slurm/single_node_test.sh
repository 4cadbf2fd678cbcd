#!/usr/bin/env bash
# Starts a single-node Slurm cluster in a temporary directory (munged, slurmctld, slurmd from the
# Debian packages slurm-wlm and munge, a minimal slurm.conf), submits a 4-chunk array job and the
# dependent merge with scripts/slurm/submit_chunks.sh, waits, and checks the merged EXR against a
# single-process render byte for byte.
# Usage: single_node_test.sh SYLVA
# Exit 0: passed. Exit 77: SKIPPED (the daemons cannot run here), said loudly on stderr — ctest
# reports it as skipped, never as passed. Anything else: failed.
set -uo pipefail
sylva=$(realpath "${1:?path to sylva}")
repo=$(cd "$(dirname "$0")/../.." && pwd)
skip() {
  echo "SKIPPED: single-node Slurm test cannot run here: $*" >&2
  exit 77
}
for tool in munged slurmctld slurmd sbatch squeue sinfo; do
  command -v "$tool" >/dev/null || skip "$tool not installed (apt-get install slurm-wlm munge)"
done
[[ $(id -u) -eq 0 ]] || skip "needs root to run slurmd"

dir=$(mktemp -d /tmp/sylva_slurm.XXXXXX)
chmod 755 "$dir"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  sleep 0.5
  for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null; done
  rm -rf "$dir"
}
trap cleanup EXIT
trap 'exit 1' TERM INT

# munge, on its own socket.
mkdir -p "$dir/munge"
chmod 700 "$dir/munge"
dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$dir/munge/munge.key"
socket="$dir/munge/munge.socket"
munged --force --key-file="$dir/munge/munge.key" --socket="$socket" --pid-file="$dir/munge/munged.pid" \
  --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" || skip "munged does not start"
for _ in $(seq 50); do [[ -f "$dir/munge/munged.pid" ]] && break; sleep 0.1; done
pids+=("$(cat "$dir/munge/munged.pid")")

host=$(hostname -s)
port=$((20000 + RANDOM % 20000))
mkdir -p "$dir/state" "$dir/spool"
cat >"$dir/slurm.conf" <<CONF
ClusterName=sylvatest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
export SLURM_CONF="$dir/slurm.conf"
slurmctld -D -i >"$dir/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D >"$dir/slurmd.out" 2>&1 &
pids+=($!)
up=0
for _ in $(seq 100); do
  if sinfo -h -o %t 2>/dev/null | grep -Eq '^(idle|mix|alloc)'; then
    up=1
    break
  fi
  sleep 0.2
done
if ((up == 0)); then
  echo "--- slurmctld log" >&2
  tail -5 "$dir/slurmctld.log" "$dir/slurmctld.out" >&2
  echo "--- slurmd log" >&2
  tail -5 "$dir/slurmd.log" "$dir/slurmd.out" >&2
  skip "the node never became idle"
fi
echo "slurm up: $(sinfo -h -o '%P %t %N')"

work="$dir/work"
mkdir -p "$work"
chmod 777 "$dir/work"
objects="$(cd "$(dirname "$0")/../.." && pwd)/data/examples/objects.toml"  # the CLI tests' small scene
args=("$objects" --res 40x24 --spp 8)
"$sylva" render -o "$work/single.exr" "${args[@]}" --threads 1 --quiet || exit 1
ids=$(SYLVA="$sylva" SPLIT=samples PNG="$work/merged.png" SBATCH_ARGS="--output=$work/slurm-%A_%a.out" \
  "$repo/scripts/slurm/submit_chunks.sh" 4 "$work/merged.exr" -- "${args[@]}" --threads 1) || exit 1
read -r array merge <<<"$ids"
echo "submitted array job $array and merge job $merge"
for _ in $(seq 600); do
  [[ -z $(squeue -h -j "$array,$merge" 2>/dev/null) ]] && break
  sleep 0.5
done
if [[ ! -f "$work/merged.exr" ]]; then
  echo "FAIL: no merged EXR; job outputs:" >&2
  tail -n 5 "$work"/*.out "$dir"/slurm*.log >&2
  exit 1
fi
ls "$work"
if cmp "$work/single.exr" "$work/merged.exr"; then
  echo "ok: 4 Slurm array chunks + dependent merge are byte-identical to the single render"
else
  echo "FAIL: the merged EXR differs from the single-process render" >&2
  exit 1
fi

# Frames as an array job (scripts/slurm/frames.sbatch): 3 frames over 2 tasks equal a local
# `--frames` render byte for byte, and a re-submitted array skips the finished frames.
wait_for() {
  for _ in $(seq 600); do
    [[ -z $(squeue -h -j "$1" 2>/dev/null) ]] && return 0
    sleep 0.5
  done
  return 1
}
mkdir -p "$work/local" "$work/anim"
chmod 777 "$work/anim"
"$sylva" render -o "$work/local/f.exr" --frames 0:2 --fps 24 "${args[@]}" --threads 1 --quiet || exit 1
submit_frames() {
  sbatch --parsable --array=0-1 --output="$work/frames-%A_%a.out" \
    --export=ALL,SYLVA="$sylva",OUT="$work/anim/f.exr",FIRST=0,LAST=2,PER_TASK=2,FPS=24,RENDER_ARGS="${args[*]} --threads 1" \
    "$repo/scripts/slurm/frames.sbatch"
}
frames=$(submit_frames) || exit 1
wait_for "$frames" || { echo "FAIL: the frames array never finished" >&2; exit 1; }
for f in 0000 0001 0002; do
  if ! cmp "$work/local/f.$f.exr" "$work/anim/f.$f.exr"; then
    echo "FAIL: frame $f of the Slurm array differs from the local render (or is missing):" >&2
    tail -n 5 "$work"/frames-*.out >&2
    exit 1
  fi
done
before=$(stat -c %Y.%s "$work"/anim/f.000?.exr)
frames=$(submit_frames) || exit 1
wait_for "$frames" || { echo "FAIL: the re-submitted frames array never finished" >&2; exit 1; }
if [[ "$before" != "$(stat -c %Y.%s "$work"/anim/f.000?.exr)" ]]; then
  echo "FAIL: a re-submitted frames array rendered finished frames again" >&2
  exit 1
fi
echo "ok: a 3-frame Slurm array equals the local --frames render and resumes by skipping finished frames"

# A detection study (scripts/slurm/submit_study.sh): a 3-task array of shards and the dependent
# collect job write the files of a local `sylva study` byte for byte (manifest, frames, annotations,
# the study's coco.json); re-submitting renders nothing again.
# shellcheck source=tests/app/tiny_study.sh
source "$repo/tests/app/tiny_study.sh"
mkdir -p "$work/study"
chmod 777 "$work/study"
write_tiny_study "$work/study"
"$sylva" study "$work/study/study.toml" -o "$work/study_local" --threads 1 --quiet || exit 1
submit_study() {
  SYLVA="$sylva" STUDY_ARGS="--threads 1" SBATCH_ARGS="--output=$work/study-%A_%a.out" \
    "$repo/scripts/slurm/submit_study.sh" 3 "$work/study/study.toml" "$work/study/out"
}
ids=$(submit_study) || exit 1
read -r array collect <<<"$ids"
wait_for "$array,$collect" || { echo "FAIL: the study jobs never finished" >&2; exit 1; }
if ! diff -r "$work/study_local" "$work/study/out" >&2; then
  echo "FAIL: the Slurm study differs from the local one (or is incomplete); job outputs:" >&2
  tail -n 5 "$work"/study-*.out >&2
  exit 1
fi
before=$(stat -c %Y.%s "$work"/study/out/frames/*)
ids=$(submit_study) || exit 1
read -r array collect <<<"$ids"
wait_for "$array,$collect" || { echo "FAIL: the re-submitted study never finished" >&2; exit 1; }
if [[ "$before" != "$(stat -c %Y.%s "$work"/study/out/frames/*)" ]]; then
  echo "FAIL: a re-submitted study rendered finished frames again" >&2
  exit 1
fi
echo "ok: a 3-shard Slurm study and its collect job equal the local study and resume by skipping finished frames"

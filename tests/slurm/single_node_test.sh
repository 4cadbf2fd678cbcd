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
args=(--res 40x24 --spp 8)
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

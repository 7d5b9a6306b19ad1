#!/usr/bin/env bash
# Slurm, for real (ctest label cluster): a single-node Slurm on this machine
# runs the sharded sweep of docs/sweeps.md, and its merged result is the
# unsharded sweep's, byte for byte.
#
#   1. munged (a fresh key), slurmctld and slurmd (one node, this host, at
#      127.0.0.1, on two free ports) start as the current user, with their
#      configuration, state, sockets and logs in a scratch folder;
#   2. docs/sweep.sbatch, the file the page documents, is submitted as it is
#      (a job array of 4 shards), with a short sweep (SWEEP_ARGS below), and
#      the merge job after it with --dependency=afterok, as the page says;
#   3. meanwhile the same sweep runs unsharded here;
#   4. the merged sweep.csv must equal the unsharded one (cmp).
# The daemons are stopped (by their process ids) and the folder removed at
# the end. A daemon that cannot start fails the test with its log: never a
# silent skip.
# Usage: slurm_sweep.sh SOURCE_DIR ARTTRACK
set -euo pipefail
src=$(cd "$1" && pwd)
arttrack=$(realpath "$2")
# The sweep of docs/sweep.sbatch made short: 18 cells of 1 s at 80x60.
sweep_args="--set duration_s=1 --set camera.width=80 --set camera.height=60
  --set scoring.converged_after_s=0.5 --methods encoders_only,full_fusion --runs 1"

say() { echo "slurm_sweep: $*"; }
scratch=$(mktemp -d /tmp/arttrack-slurm.XXXXXX)
pids=()
jobs_submitted=()
logs_shown=0
show_logs() {
  [ "$logs_shown" = 1 ] && return
  logs_shown=1
  for f in "$scratch"/log/* "$scratch"/work/logs/*; do
    [ -f "$f" ] || continue
    echo "---- $f (last 25 lines)" >&2
    tail -n 25 "$f" >&2
  done
}
fail() {
  echo "slurm_sweep: FAIL: $*" >&2
  show_logs
  exit 1
}
cleanup() {
  local code=$?
  if ((${#jobs_submitted[@]})) && [ -n "${SLURM_CONF:-}" ]; then
    scancel "${jobs_submitted[@]}" 2> /dev/null || true
  fi
  # Stop the daemons this test started, newest first, by their ids.
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill "${pids[i]}" 2> /dev/null || true
    for _ in $(seq 50); do kill -0 "${pids[i]}" 2> /dev/null || break; sleep 0.1; done
    kill -9 "${pids[i]}" 2> /dev/null || true
  done
  wait 2> /dev/null || true
  [ "$code" = 0 ] || show_logs
  rm -rf "$scratch"
}
trap cleanup EXIT

for tool in munged mungekey munge slurmctld slurmd sbatch squeue scontrol scancel sinfo; do
  command -v "$tool" > /dev/null ||
    fail "'$tool' is not installed: apt-get install slurm-wlm munge (tools/setup.sh installs them)"
done

# ---- 1. the daemons ----
user=$(id -un)
host=$(hostname -s)
mkdir -p "$scratch"/{key,run,state,spool,log,work}
# munged wants its socket's folder open to all and its key folder private.
chmod 755 "$scratch" "$scratch/run"
chmod 700 "$scratch/key"
mungekey --create --keyfile="$scratch/key/munge.key" ||
  fail "mungekey could not create a key in $scratch/key"
munged --foreground --socket="$scratch/run/munge.sock" --key-file="$scratch/key/munge.key" \
  --pid-file="$scratch/run/munged.pid" --seed-file="$scratch/key/munged.seed" \
  --log-file="$scratch/log/munged.log" > "$scratch/log/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$scratch/run/munge.sock" ] && break; sleep 0.1; done
munge --socket="$scratch/run/munge.sock" --no-input 2> "$scratch/log/munge_check.log" |
  unmunge --socket="$scratch/run/munge.sock" > /dev/null 2>> "$scratch/log/munge_check.log" ||
  fail "munged did not start as user $user (a credential did not round-trip; munged.out says: $(tail -n 3 "$scratch/log/munged.out" | tr '\n' ' '))"

read -r ctld_port slurmd_port < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks:
    s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))')
node=$(slurmd -C | head -n 1)
[[ "$node" == NodeName=* ]] || fail "slurmd -C does not describe this node: $node"
export SLURM_CONF="$scratch/slurm.conf"
cat > "$SLURM_CONF" << EOF
ClusterName=arttrack-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$scratch/run/munge.sock
CredType=cred/munge
StateSaveLocation=$scratch/state
SlurmdSpoolDir=$scratch/spool
SlurmctldPidFile=$scratch/run/slurmctld.pid
SlurmdPidFile=$scratch/run/slurmd.pid
SlurmctldLogFile=$scratch/log/slurmctld.log
SlurmdLogFile=$scratch/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=600
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -D -i > "$scratch/log/slurmctld.out" 2>&1 &
pids+=($!)
ctld_pid=$!
up=0
for _ in $(seq 100); do
  kill -0 "$ctld_pid" 2> /dev/null || break
  if scontrol ping 2> /dev/null | grep -q "is UP"; then up=1 && break; fi
  sleep 0.2
done
[ "$up" = 1 ] || fail "slurmctld did not start as user $user: $(tail -n 3 "$scratch/log/slurmctld.out" "$scratch/log/slurmctld.log" 2> /dev/null | tr '\n' ' ')"
slurmd -D > "$scratch/log/slurmd.out" 2>&1 &
pids+=($!)
slurmd_pid=$!
idle=0
for _ in $(seq 150); do
  kill -0 "$slurmd_pid" 2> /dev/null || break
  if [ "$(sinfo -h -o %T 2> /dev/null)" = idle ]; then idle=1 && break; fi
  sleep 0.2
done
[ "$idle" = 1 ] || fail "slurmd did not start or register as user $user (node state '$(sinfo -h -o %T 2> /dev/null)'): $(tail -n 3 "$scratch/log/slurmd.out" "$scratch/log/slurmd.log" 2> /dev/null | tr '\n' ' ')"
say "single-node Slurm up as $user ($node; ports $ctld_port, $slurmd_port)"

# ---- 2. the documented job array, and the merge after it ----
cd "$scratch/work"
mkdir -p logs
start=$SECONDS
array_job=$(ARTTRACK="$arttrack" SCENARIO="$src/scenarios/default.yaml" SWEEP_ARGS="$sweep_args" \
  sbatch --parsable "$src/docs/sweep.sbatch") || fail "sbatch docs/sweep.sbatch was refused"
array_job=${array_job%%;*}
jobs_submitted+=("$array_job")
merge_job=$(sbatch --parsable --dependency="afterok:$array_job" --kill-on-invalid-dep=yes \
  --output=logs/merge.log --wrap "$arttrack merge parts/* --out all") ||
  fail "sbatch of the merge job was refused"
merge_job=${merge_job%%;*}
jobs_submitted+=("$merge_job")
say "submitted array job $array_job (docs/sweep.sbatch) and merge job $merge_job"

# ---- 3. the unsharded sweep, meanwhile ----
# shellcheck disable=SC2086  # sweep_args: words
"$arttrack" sweep "$src/scenarios/default.yaml" --grid camera.latency_s=0:0.1:0.02 \
  --grid 'encoders[0].offset_deg=0,4,8' $sweep_args --out unsharded > logs/unsharded.log 2>&1 ||
  fail "the unsharded sweep failed"

# ---- 4. wait, then compare ----
deadline=$((SECONDS + 900))
while [ -n "$(squeue -h -j "$array_job,$merge_job" 2> /dev/null)" ]; do
  [ "$SECONDS" -lt "$deadline" ] || fail "the jobs did not finish in 900 s: $(squeue -j "$array_job,$merge_job" | tr '\n' ' ')"
  sleep 1
done
states=$(scontrol show job "$array_job" | grep -o "JobState=[A-Z_]*" | sort | uniq -c | tr -s ' \n' ' ')
merge_state=$(scontrol show job "$merge_job" | grep -o "JobState=[A-Z_]*")
[ "$merge_state" = JobState=COMPLETED ] ||
  fail "the merge job ended $merge_state (array tasks: $states)"
for i in 0 1 2 3; do
  [ -f "parts/$i/sweep.csv" ] || fail "shard $i wrote no parts/$i/sweep.csv"
done
cmp all/sweep.csv unsharded/sweep.csv ||
  fail "the merged sweep.csv differs from the unsharded one"
cells=$(($(wc -l < all/sweep.csv) - 1))
say "4 shards on Slurm ($states), merged: sweep.csv identical to the unsharded sweep ($cells rows) in $((SECONDS - start)) s"

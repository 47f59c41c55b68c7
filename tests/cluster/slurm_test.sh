#!/usr/bin/env bash
# The Slurm recipes of examples/cluster, run for real: a one-node Slurm (munged, slurmctld and
# slurmd on this machine, a minimal slurm.conf, free ports, everything under a temporary folder)
# is started, both recipes are submitted with `sbatch --wait`, and their images are compared
# with the same renders in one process. The job array is submitted twice: the second time every
# frame is skipped. Exit 77 (skipped) when Slurm, munge or mpirun is not installed, or when this
# machine cannot run the daemons (not root, or munged/slurmd refuse to start: the logs are
# printed); a recipe that fails on a running Slurm is a failure.
# Usage: slurm_test.sh ANAMORPH_BINARY SOURCE_DIR
set -euo pipefail
bin=$1
src=$2
for tool in munged slurmctld slurmd sbatch mpirun; do
  if ! command -v "$tool" >/dev/null; then
    echo "SKIP: $tool not found (scripts/install-deps installs slurm-wlm, munge and openmpi-bin)"
    exit 77
  fi
done

if [ "$(id -u)" -ne 0 ]; then
  echo "SKIP: slurmd runs jobs as their users and must be started as root; this test is not root"
  exit 77
fi

dir=$(mktemp -d /tmp/anamorph-slurm.XXXXXX)
chmod 700 "$dir"
mkdir -p "$dir/state" "$dir/spool" "$dir/out"
cleanup() {
  for pid in "$dir/slurmd.pid" "$dir/slurmctld.pid"; do
    [ -f "$pid" ] && kill "$(cat "$pid")" 2>/dev/null || true
  done
  munged -S "$dir/munge.sock" -s >/dev/null 2>&1 || true
  sleep 0.5
  rm -rf "$dir"
}
trap cleanup EXIT

free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
host=$(hostname -s)
cpus=$(nproc)

# munge: Slurm's authentication, with a key of our own on a socket of our own.
head -c 1024 /dev/urandom >"$dir/munge.key"
chmod 400 "$dir/munge.key"
if ! munged -f --key-file="$dir/munge.key" --socket="$dir/munge.sock" \
  --log-file="$dir/munged.log" --pid-file="$dir/munged.pid" --seed-file="$dir/munged.seed"; then
  echo "SKIP: munged does not start on this machine:"
  cat "$dir/munged.log" 2>/dev/null || true
  exit 77
fi

cat >"$dir/slurm.conf" <<CONF
ClusterName=anamorphtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/munge
AuthInfo=socket=$dir/munge.sock
CredType=cred/munge
SlurmUser=$(id -un)
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=2000 State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
export SLURM_CONF=$dir/slurm.conf
slurmctld -i || true  # (a daemon that cannot start shows in sinfo and its log below)
slurmd || true
for _ in $(seq 100); do
  sinfo -h -o %T 2>/dev/null | grep -q idle && break
  sleep 0.2
done
if ! sinfo -h -o %T 2>/dev/null | grep -q idle; then
  echo "SKIP: a one-node Slurm does not come up on this machine:"
  tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" || true
  exit 77
fi
echo "slurm is up: $(sinfo -h)"

fail() {
  echo "FAIL: $*"
  tail -n 30 "$dir"/*.txt 2>/dev/null || true
  exit 1
}
same() {  # two images with the same pixels
  local r
  r=$("$bin" compare "$1" "$2" | awk '$1 == "rmse" { print $2 }')
  [ "$r" = "0" ] || fail "$1 differs from $2 (rmse $r)"
}

# 1. The job array: 6 frames over 3 array tasks, on one node, 1 CPU each.
scene=$src/examples/apps/coin_animation.toml
extra="--width 96 --height 72"
export ANAMORPH=$bin SCENE=$scene OUTPUT=$dir/out/f_%d.png LAST=5 EXTRA=$extra
timeout 300 sbatch --wait --array=0-2 --cpus-per-task=1 -o "$dir/array_%a.txt" \
  "$src/examples/cluster/frames.sbatch" >/dev/null || fail "the job array failed"
"$bin" render "$scene" $extra --frames 0:5 -o "$dir/one_%d.png" -q
for f in 0 1 2 3 4 5; do
  [ -f "$dir/out/f_$f.png" ] || fail "frame $f was not written"
  same "$dir/out/f_$f.png" "$dir/one_$f.png"
done
ls "$dir"/out/*.ckpt >/dev/null 2>&1 && fail "checkpoints left after the frames were done"
echo "job array: frames 0-5 rendered by 3 array tasks equal one process"
# Submitted again: nothing left to render, every frame skipped and untouched.
before=$(stat -c %Y "$dir"/out/f_*.png | sort | md5sum)
timeout 300 sbatch --wait --array=0-2 --cpus-per-task=1 -o "$dir/again_%a.txt" \
  "$src/examples/cluster/frames.sbatch" >/dev/null || fail "the resubmitted job array failed"
[ "$(cat "$dir"/again_*.txt | grep -c 'exists: skipped')" = 6 ] || fail "frames were not skipped"
[ "$(stat -c %Y "$dir"/out/f_*.png | sort | md5sum)" = "$before" ] || fail "frames were rewritten"
echo "job array again: all 6 frames skipped"

# 2. One frame across MPI ranks inside a Slurm allocation: 3 tasks (the head and 2 workers).
unset LAST
export SCENE=$src/examples/apps/fisheye_180.toml OUTPUT=$dir/out/big.png
export EXTRA="--width 256 --height 256 --spp 2" MPIRUN_OPTIONS="--allow-run-as-root --oversubscribe"
"$bin" render "$SCENE" $EXTRA -o "$dir/one_big.png" -q
export EXTRA="$EXTRA --stats $dir/big.json"
timeout 300 sbatch --wait --nodes=1 --ntasks=3 --cpus-per-task=1 -o "$dir/big.txt" \
  "$src/examples/cluster/big-frame.sbatch" >/dev/null || fail "the MPI job failed"
[ -f "$OUTPUT" ] || fail "the MPI job wrote no image"
same "$OUTPUT" "$dir/one_big.png"
[ -f "$OUTPUT.ckpt" ] && fail "the MPI job's checkpoint outlived it"
for rank in 1 2; do  # both workers rendered tiles (--stats names each tile's rank)
  grep -q "\"rank\": $rank" "$dir/big.json" || fail "rank $rank rendered no tile"
done
echo "MPI job in Slurm: 3 ranks equal one process"
echo "PASS"

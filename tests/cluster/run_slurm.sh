#!/usr/bin/env bash
# The ci workflow on a real SLURM cluster, compared with a local run.
#
#   bash tests/cluster/run_slurm.sh          # as root, on Debian 12 or similar; a few minutes
#
# 1. installs Debian's slurm-wlm when slurmctld is missing (exit 77, "skipped", when it cannot),
#    and isorock with its extra cluster (requirements/lock-cluster.txt) into .venv when the plugin is missing;
# 2. writes a one-node cluster's /etc/slurm/slurm.conf (any file there is put back at the end) and
#    starts slurmctld and slurmd as background daemons, keeping their PIDs;
# 3. runs config/ci.yaml twice from empty working directories: locally (the default profile) and
#    through `isorock report --profile slurm` (every job an sbatch job on the cluster);
# 4. compares the two results/isorock.h5, every number (tests/cluster/compare_stores.py);
# 5. stops the daemons it started, by PID, whatever happened.
# Exit 0 only when both runs succeeded and the stores hold identical numbers; 77 when the cluster
# cannot be set up here (not root, no package archive), with the reason; 1 otherwise.
#
# Pitfalls met on the way (slurm-wlm 22.05.8, snakemake 9.27, snakemake-executor-plugin-slurm 2.8.0):
# - No systemd in a container: the daemons run in the foreground (-D) under `&`, and are stopped
#   by the PIDs this script keeps, never by `pkill` (other clusters on the machine are not ours).
# - AuthType=auth/none with CredType=cred/none works in 22.05 (removed in later releases), so no
#   munge daemon is needed. ProctrackType=proctrack/linuxproc and TaskPlugin=task/none: no cgroups.
# - DefMemPerCPU must be set: without it a job that asks for no memory is given the whole node,
#   and jobs run one at a time.
# - The plugin checks job states with `sacct` whenever the binary exists; without accounting
#   (no slurmdbd) sacct fails and the workflow waits forever, ignoring SIGTERM. We pass
#   --slurm-status-command squeue, which the plugin honours only when the cluster's MinJobAge is at
#   least 3x --slurm-init-seconds-before-status-checks (else it silently falls back to sacct).
#   A finished job stays visible to squeue for MinJobAge seconds: 300 here.
# - The default 40 s before the first status check (and +10 s per idle check after it) makes a
#   short DAG spend most of its time waiting: --slurm-init-seconds-before-status-checks 2 here.
# - No accounts without slurmdbd: --slurm-no-account, else the plugin asks sacct/sacctmgr for one.
# - The plugin's job side (snakemake-executor-plugin-slurm-jobstep) strips every SLURM_* variable,
#   SLURM_CONF included, before its srun: the configuration must be at the default path
#   /etc/slurm/slurm.conf, not in a SLURM_CONF of our own.
# - Jobs inherit this shell's environment (sbatch --export=ALL), so PATH must hold the .venv's
#   python: the job runs `python -m snakemake`.
# - A group job asks for the threads of all its jobs that can run at once, unless --cores caps it
#   (under the slurm executor --cores is the most CPUs one SLURM job asks for, not a total): a group
#   of 3 two-thread jobs asked for 6 CPUs and stayed pending forever (PartitionConfig) on this 2-CPU
#   node. We pass --cores $CPUS; the profile's default is 8.
# - `--export` in the slurm_extra resource is refused by the plugin, and the refusal (raised in its
#   submission thread) leaves the workflow waiting forever with nothing submitted. The profile sets
#   NUMBA_CACHE_DIR with `precommand` instead, which runs in the job before its Snakemake.
# - The node's RealMemory must not exceed what slurmd detects, or the node is drained as
#   "Low RealMemory": we take it from `slurmd -C`.
set -uo pipefail

REPO="$(cd "$(dirname "$0")/../.." && pwd)"
cd "$REPO"
VENV="${VENV:-$REPO/.venv}"
CONF=/etc/slurm/slurm.conf
WORK="$(mktemp -d /tmp/isorock-slurm.XXXXXX)"
chmod 755 "$WORK"
PIDS=()
CONF_BACKUP=""

skip() { echo "run_slurm: SKIPPED: $*" >&2; exit 77; }
fail() { echo "run_slurm: FAILED: $*" >&2; exit 1; }
now() { date +%s.%N; }
elapsed() { python3 -c "print(f'{$2 - $1:.2f}')"; }

cleanup() {
  local rc=$?
  if command -v scancel >/dev/null && [ ${#PIDS[@]} -gt 0 ]; then
    scancel --quiet --user "$(id -un)" 2>/dev/null || true
  fi
  for pid in "${PIDS[@]}"; do
    kill "$pid" 2>/dev/null || true
  done
  for pid in "${PIDS[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then kill -9 "$pid" 2>/dev/null || true; fi
  done
  [ ${#PIDS[@]} -gt 0 ] && echo "run_slurm: stopped the daemons (PIDs ${PIDS[*]})"
  if [ -n "$CONF_BACKUP" ]; then
    mv -f "$CONF_BACKUP" "$CONF"
  elif [ -f "$CONF" ] && grep -q "written by isorock tests/cluster/run_slurm.sh" "$CONF"; then
    rm -f "$CONF"
  fi
  if [ "$rc" -eq 0 ] && [ -z "${KEEP:-}" ]; then rm -rf "$WORK"; else echo "run_slurm: files kept in $WORK"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# ---------------------------------------------------------------- 1. packages
[ "$(id -u)" -eq 0 ] || skip "needs root (it writes $CONF and starts slurmd, which runs jobs as their users)"
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null; then
  command -v apt-get >/dev/null || skip "slurmctld is not installed and there is no apt-get to install slurm-wlm"
  echo "run_slurm: installing Debian's slurm-wlm"
  if ! (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm) \
    >"$WORK/apt.log" 2>&1; then
    tail -5 "$WORK/apt.log" >&2
    skip "apt-get install slurm-wlm failed (no package archive reachable?)"
  fi
fi
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV" || fail "cannot create $VENV"
if ! "$VENV/bin/python" -c "import snakemake_executor_plugin_slurm, isorock" 2>/dev/null; then
  echo "run_slurm: installing isorock and its extra cluster from the lock files into $VENV"
  "$VENV/bin/pip" install -q --no-deps -r "$REPO/requirements/lock-py311.txt" \
    -r "$REPO/requirements/lock-cluster.txt" -e "$REPO" || skip "pip install of the lock files failed (no package index?)"
fi
export PATH="$VENV/bin:$PATH"
RECORDS="${ISOROCK_RECORDS:-$REPO/../shared/records}"
[ -d "$RECORDS" ] || fail "config/ci.yaml needs the Table 1 records: none in \$ISOROCK_RECORDS or $REPO/../shared/records"
RECORDS="$(cd "$RECORDS" && pwd)"
echo "run_slurm: $(slurmctld -V), $(snakemake --version | sed 's/^/snakemake /'), plugin $("$VENV/bin/python" -c \
  'from importlib.metadata import version; print(version("snakemake-executor-plugin-slurm"))')"

# ---------------------------------------------------------------- 2. a one-node cluster
HOST="$(hostname -s)"
read -r CPUS MEM < <(slurmd -C | tr ' ' '\n' | awk -F= '/^CPUs=/{c=$2} /^RealMemory=/{m=$2} END{print c, m}')
[ -n "$CPUS" ] && [ -n "$MEM" ] || fail "slurmd -C did not report the node's CPUs and memory"
MEM=$((MEM * 9 / 10))
mkdir -p "$WORK/spool" "$WORK/state" /etc/slurm
if [ -f "$CONF" ]; then CONF_BACKUP="$WORK/slurm.conf.before"; cp -p "$CONF" "$CONF_BACKUP"; fi
cat >"$CONF" <<EOF
# written by isorock tests/cluster/run_slurm.sh (removed, or the former file put back, at its end)
ClusterName=isorock-test
SlurmctldHost=$HOST
AuthType=auth/none
CredType=cred/none
SlurmUser=root
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/slurmctld.log
SlurmdLogFile=$WORK/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=300
ReturnToService=2
DefMemPerCPU=$((MEM / CPUS))
NodeName=$HOST CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=main Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
t0=$(now)
slurmctld -D -i >"$WORK/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D >"$WORK/slurmd.out" 2>&1 &
PIDS+=($!)
up=""
for _ in $(seq 120); do
  state="$(sinfo -h -n "$HOST" -o %T 2>/dev/null || true)"
  if [ "$state" = "idle" ]; then up=1; break; fi
  sleep 0.5
done
if [ -z "$up" ]; then
  tail -5 "$WORK/slurmctld.log" "$WORK/slurmd.log" >&2 2>/dev/null
  fail "the node did not come up idle (state: ${state:-none}); logs in $WORK"
fi
t_up=$(now)
echo "run_slurm: one-node cluster $HOST ($CPUS CPUs, $MEM MB) up in $(elapsed "$t0" "$t_up") s (slurmctld ${PIDS[0]}, slurmd ${PIDS[1]})"
# a first job proves that jobs run (and how long a bare job takes)
t0=$(now)
srun -N1 -n1 true || fail "srun true failed on the new cluster"
echo "run_slurm: srun true: $(elapsed "$t0" "$(now)") s"

# ---------------------------------------------------------------- 3. the two runs
run() {  # run NAME [isorock report options...]: the ci workflow from an empty working directory
  local name=$1; shift
  mkdir -p "$WORK/$name"
  local t0; t0=$(now)
  if ! isorock report --configfile "$REPO/config/ci.yaml" --records "$RECORDS" --directory "$WORK/$name" \
    --cores "$CPUS" "$@" >"$WORK/$name.log" 2>&1; then
    tail -30 "$WORK/$name.log" >&2
    fail "the $name run failed (log: $WORK/$name.log)"
  fi
  local dt; dt=$(elapsed "$t0" "$(now)")
  echo "run_slurm: $name run (workflow and report): $dt s; results in $WORK/$name/results"
  eval "T_$name=$dt"
}
run local
# --cores: the most CPUs one SLURM job asks for (the node has $CPUS); the three plugin options: see the
# pitfalls at the top (no accounting database on this cluster)
run slurm --profile slurm -- --slurm-status-command squeue --slurm-init-seconds-before-status-checks 2 \
  --slurm-no-account
n_jobs=$(awk '/^Job stats:/{f=1} f && /^total/{print $2 - 1; exit}' "$WORK/slurm.log")  # less the target, all
n_sub=$(grep -c "has been submitted with SLURM jobid" "$WORK/slurm.log" || true)
echo "run_slurm: $n_jobs Snakemake jobs ran as $n_sub SLURM jobs; wall time local $T_local s, through SLURM $T_slurm s"
if grep -q "Falling back to 'sacct'" "$WORK/slurm.log"; then
  fail "the plugin fell back to sacct (MinJobAge too low for squeue status checks)"
fi

# ---------------------------------------------------------------- 4. the same numbers
"$VENV/bin/python" "$REPO/tests/cluster/compare_stores.py" \
  "$WORK/local/results/isorock.h5" "$WORK/slurm/results/isorock.h5" || fail "the stores differ"
echo "run_slurm: PASSED: the SLURM run's results/isorock.h5 holds the numbers of the local run"

# ---------------------------------------------------------------- 5. cluster jobs of a dead run
# a job still working in the folder (as those of a run whose login-node Snakemake died) stops a new run
jid=$(sbatch --parsable --chdir "$WORK/slurm" --wrap "sleep 60" --output /dev/null) || fail "sbatch failed"
for _ in $(seq 100); do squeue --noheader -j "$jid" -t R | grep -q . && break; sleep 0.1; done
if isorock report --configfile "$REPO/config/ci.yaml" --records "$RECORDS" --directory "$WORK/slurm" \
  --cores "$CPUS" --profile slurm --no-run >"$WORK/busy.log" 2>&1; then
  scancel "$jid"; fail "a run started while SLURM job $jid worked in its folder"
fi
scancel "$jid"
grep -q "cluster job(s) of another run (SLURM job $jid) are working in this folder" "$WORK/busy.log" ||
  { cat "$WORK/busy.log" >&2; fail "the refusal does not name SLURM job $jid"; }
echo "run_slurm: PASSED: a run is refused while a SLURM job ($jid) of another works in its folder"

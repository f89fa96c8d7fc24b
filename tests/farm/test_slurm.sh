#!/bin/sh
# test_slurm.sh — the README's Slurm recipe (tools/slurm/render.sbatch and
# the merge as an afterok job) on a real Slurm: a private one-node cluster
# started here from a scratch folder (munged with its own key and socket,
# slurmctld -D, slurmd -D; no systemd, no cgroups), then stopped by pid.
#   - a 4-task array merged by a dependent job equals one render bit for bit;
#   - with one task failing, the merge is cancelled, never run (sbatch --wait
#     returns 0 for a cancelled job, so the job's state is read from the
#     completion log), and `strata merge --partial` names the missing range;
#   - afterwards no daemon of the cluster runs or listens.
# Skipped, saying so, where slurm-wlm and munge are not installed (make deps
# installs them). TAP output.
. tests/tap.sh
for tool in munged slurmctld slurmd sbatch sinfo; do
    if ! command -v "$tool" > /dev/null && [ ! -x "/usr/sbin/$tool" ]; then
        echo "1..0 # SKIP slurm-wlm and munge are not installed (make deps installs them)"
        exit 0
    fi
done
PATH=$PATH:/usr/sbin
case $S in /*) ;; *) S=$PWD/$S ;; esac
export STRATA=$S
SCRIPT=$PWD/tools/slurm/render.sbatch
OPTS="--width 32 --height 24 --spp 16 --sampler stratified --seed 3 --quiet"
D=$T/cluster
pids=""

# A TCP port nothing listens on now (the kernel's choice), and whether one is
# listened on.
free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
listening() { python3 -c 'import socket, sys; s = socket.socket(); sys.exit(s.connect_ex(("127.0.0.1", int(sys.argv[1]))) != 0)' "$1"; }

# Each daemon in the foreground, in the background of this shell: its pid is $!.
start() { "$@" >> "$D/daemons.log" 2>&1 & pids="$pids $!"; }

# Stops every daemon started here, by pid: TERM, then KILL after 10 s.
stop_cluster() {
    for p in $pids; do kill "$p" 2> /dev/null; done
    for p in $pids; do
        i=0
        while kill -0 "$p" 2> /dev/null && [ $i -lt 50 ]; do sleep 0.2; i=$((i + 1)); done
        kill -9 "$p" 2> /dev/null
        wait "$p" 2> /dev/null
    done
}
trap 'stop_cluster; rm -rf "$T"' EXIT
trap 'exit 1' INT TERM

# munged checks that its socket's folders are not writable by others and
# can be entered (mktemp's folder is 0700); its key must be private.
chmod 711 "$T"
mkdir -p "$D/munge" "$D/state" "$D/spool" "$D/run"
chmod 755 "$D" "$D/munge"
dd if=/dev/urandom of="$D/munge.key" bs=1024 count=1 2> /dev/null
chmod 600 "$D/munge.key"
start munged --foreground --socket="$D/munge/socket" --key-file="$D/munge.key" \
    --pid-file="$D/munge/munged.pid" --seed-file="$D/munge/seed" --log-file="$D/munge/log"
CTLD_PORT=$(free_port)
SLURMD_PORT=$(free_port)
user=$(id -un)
# MinJobAge and batch_sched_delay let sbatch --wait return in seconds; the
# completion log keeps every job's final state after slurmctld forgets it.
# DependencyParameters=kill_invalid_depend is left out on purpose: the
# recipe's --kill-on-invalid-dep=yes must cancel the merge by itself.
cat > "$D/slurm.conf" << EOF
ClusterName=strata-test
SlurmctldHost=localhost
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$D/munge/socket
StateSaveLocation=$D/state
SlurmdSpoolDir=$D/spool
SlurmctldPidFile=$D/run/slurmctld.pid
SlurmdPidFile=$D/run/slurmd.pid
SlurmctldLogFile=$D/slurmctld.log
SlurmdLogFile=$D/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$D/jobs.txt
MpiDefault=none
ReturnToService=2
MinJobAge=5
SchedulerParameters=batch_sched_delay=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$D/slurm.conf"
i=0
while [ ! -S "$D/munge/socket" ] && [ $i -lt 50 ]; do sleep 0.2; i=$((i + 1)); done
start slurmctld -D -f "$SLURM_CONF"
start slurmd -D -N localhost -f "$SLURM_CONF"
i=0
while [ "$(sinfo -h -n localhost -o %T 2> /dev/null)" != idle ] && [ $i -lt 150 ]; do
    sleep 0.2
    i=$((i + 1))
done
state=$(sinfo -h -n localhost -o %T 2> /dev/null)
check "a private one-node cluster comes up (node idle)" '[ "$state" = idle ]' "(node: '$state')"
if [ "$state" != idle ]; then
    tail -n 20 "$D/daemons.log" "$D/slurmctld.log" "$D/slurmd.log" 2> /dev/null | sed 's/^/# /'
    echo "1..$n"
    exit 1
fi

# The final state of a job (its id) or of an array's task (job id, task id),
# from the completion log.
job_state() { sed -n "s/^JobId=$1 .*JobState=\([A-Z_]*\).*/\1/p" "$D/jobs.txt"; }
task_state() { sed -n "s/.*JobState=\([A-Z_]*\) .*ArrayJobId=$1 ArrayTaskId=$2 .*/\1/p" "$D/jobs.txt"; }

# The recipe, as render.sbatch's header gives it: a 4-task array, then the
# merge once every task succeeded. $1: the folder it runs in.
recipe() {
    mkdir -p "$1"
    array=$(cd "$1" && sbatch --parsable --array=0-3 -c 1 "$SCRIPT" $OPTS)
    merge=$(cd "$1" && timeout 300 sbatch --parsable --wait --dependency="afterok:$array" \
        --kill-on-invalid-dep=yes --wrap "\"$S\" merge part-*.exr -o final.exr")
}

recipe "$T/ok"
for k in 0 1 2 3; do
    check "array task $k completed" '[ "$(task_state "$array" $k)" = COMPLETED ]' \
        "(got '$(task_state "$array" $k)'; $(cat "$T/ok/part-$k.log" 2> /dev/null | head -3))"
done
check "the afterok merge ran" '[ "$(job_state "$merge")" = COMPLETED ] && [ -s "$T/ok/final.exr" ]'
$S render $OPTS -o "$T/whole.exr"
$S diff "$T/whole.exr" "$T/ok/final.exr" > "$T/diff" 2>&1
check "the merged image equals one render bit for bit" \
    'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"

# Part 2 of 4 fails (a binary that refuses it); the rest is the recipe.
cat > "$T/failing" << EOF
#!/bin/sh
case " \$* " in *" --part 2/4 "*) echo "part 2 fails on purpose" >&2; exit 1 ;; esac
exec "$S" "\$@"
EOF
chmod +x "$T/failing"
STRATA=$T/failing recipe "$T/fail"
check "the failing task failed" '[ "$(task_state "$array" 2)" = FAILED ]' "(got '$(task_state "$array" 2)')"
check "the merge was cancelled, not run" \
    '[ "$(job_state "$merge")" = CANCELLED ] && [ ! -e "$T/fail/final.exr" ]' "(got '$(job_state "$merge")')"
$S merge --partial "$T/fail"/part-*.exr -o "$T/partial.exr" 2> "$T/err"
# --spp 16 in 4 parts: part 2 holds samples 8..11
check "merge --partial names the missing range" \
    'grep -q "^strata: note: samples 8:12 are in no part" "$T/err" && [ -s "$T/partial.exr" ]' "($(cat "$T/err"))"

i=0
while [ -n "$(squeue -h 2> /dev/null)" ] && [ $i -lt 50 ]; do sleep 0.2; i=$((i + 1)); done
stop_cluster
alive=""
for p in $pids; do kill -0 "$p" 2> /dev/null && alive="$alive $p"; done
check "every daemon started here has stopped" '[ -z "$alive" ]' "(still running:$alive)"
check "nothing listens on the cluster's ports" \
    '! listening "$CTLD_PORT" && ! listening "$SLURMD_PORT" && [ ! -S "$D/munge/socket" ]'
pids=""
echo "1..$n"

#!/usr/bin/env bash
# slurm_one_node.sh -- bring up / tear down a private one-node Slurm cluster for
# the sweep test (tests/app/sweep_slurm.sh)
# (munged + slurmctld + slurmd) without systemd, everything under DIR.
#
# Usage:
#   slurm_one_node.sh up   DIR   # start; prints "export SLURM_CONF=..." on stdout
#   slurm_one_node.sh down DIR   # stop the daemons started by `up DIR` (by pid files)
#
# Exit codes of `up`: 0 = node is idle and ready; 77 = cannot run here (one-line
# reason on stderr; the caller should skip); 2 = usage error.
#
# Tunables (env):
#   SLURM_ONE_NODE_AUTH     munge (default) | none   -- none = auth/none + cred/none, no munged
#   SLURM_ONE_NODE_TIMEOUT  seconds to wait for the node to become idle (default 60)
#   SLURM_ONE_NODE_VERBOSE=1  on failure, also copy the daemons' last log lines to stderr
#   SLURM_ONE_NODE_CTLD_PORT / SLURM_ONE_NODE_SLURMD_PORT  fixed ports (default: pick free ones)
#
# Needs: Debian's slurmctld slurmd slurm-client (they pull in munge), and root
# (slurmd must be able to run jobs as the submitting user).
set -u

PROG=${0##*/}

skip() { echo "$PROG: SKIP: $*" >&2; exit 77; }
die()  { echo "$PROG: $*" >&2; exit 2; }

# Is TCP port $1 free on this machine?
port_free() {
    ! ss -Htln "sport = :$1" 2>/dev/null | grep -q .
}

pick_port() { # pick_port START -> first free port >= START (skipping $2 if given)
    local p=$1
    while [ "$p" -lt 65000 ]; do
        if [ "$p" != "${2:-}" ] && port_free "$p"; then echo "$p"; return 0; fi
        p=$((p + 1))
    done
    return 1
}

pid_alive() { [ -n "${1:-}" ] && kill -0 "$1" 2>/dev/null; }

kill_tree() { # SIGKILL a process and all its descendants (children first)
    local c
    kill -STOP "$1" 2>/dev/null
    for c in $(pgrep -P "$1" 2>/dev/null); do kill_tree "$c"; done
    kill -KILL "$1" 2>/dev/null
}

cmd_down() {
    local dir=$1 f pid pids="" i name
    [ -d "$dir/run" ] || return 0
    # SIGTERM all three at once (sequential stops take ~6 s, parallel ~2 s)
    for name in slurmd slurmctld munged; do
        f=$dir/run/$name.pid
        [ -s "$f" ] || continue
        pid=$(cat "$f" 2>/dev/null)
        # only signal it if it really is that daemon (pid files can outlive reboots)
        if pid_alive "$pid" && [ "$(cat /proc/$pid/comm 2>/dev/null)" = "$name" ]; then
            kill -TERM "$pid" 2>/dev/null && pids="$pids $pid"
        fi
    done
    for i in $(seq 1 150); do      # up to 15 s
        local left=""
        for pid in $pids; do pid_alive "$pid" && left="$left $pid"; done
        pids=$left
        [ -z "$pids" ] && break
        sleep 0.1
    done
    for pid in $pids; do
        echo "$PROG: pid $pid ignored SIGTERM, sending SIGKILL" >&2
        kill -KILL "$pid" 2>/dev/null
    done
    rm -f "$dir"/run/{slurmd,slurmctld,munged}.pid
    # leftover slurmstepd of this cluster (only if a job was still running when we
    # stopped): they are reparented to init; slurmd passed its SLURM_CONF on to them.
    for pid in $(pgrep -x slurmstepd 2>/dev/null); do
        if tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qxF "SLURM_CONF=$dir/etc/slurm.conf"; then
            kill_tree "$pid"
        fi
    done
    return 0
}

# tail_log FILE...: with SLURM_ONE_NODE_VERBOSE=1, copy the logs' last lines to stderr
tail_log() {
    [ "${SLURM_ONE_NODE_VERBOSE:-0}" = 1 ] || return 0
    local f; for f; do [ -f "$f" ] && tail -n 5 "$f" | sed "s|^|  ${f##*/}: |" >&2; done
}
# why FILE...: the last fatal/error line of the logs, for the one-line skip reason
why() {
    local f l=""
    for f; do [ -f "$f" ] && l=$(grep -hE 'fatal|error|Error' "$f" | grep -v -e pmix -e 'state file' -e 'backup state' -e MailProg | tail -n 1); [ -n "$l" ] && break; done
    printf '%s' "${l:+: $l}"
}

cmd_up() {
    local dir=$1
    local auth=${SLURM_ONE_NODE_AUTH:-munge}
    local timeout=${SLURM_ONE_NODE_TIMEOUT:-60}
    local b

    # ---- preconditions -> 77 -------------------------------------------------
    for b in slurmctld slurmd sinfo sbatch squeue scontrol; do
        command -v "$b" >/dev/null 2>&1 || skip "'$b' not found (apt-get install slurmctld slurmd slurm-client)"
    done
    if [ "$auth" = munge ]; then
        command -v munged >/dev/null 2>&1 || skip "'munged' not found (apt-get install munge)"
    fi
    [ "$(id -u)" = 0 ] || skip "must run as root (slurmd needs root to launch jobs)"
    command -v ss >/dev/null 2>&1 || skip "'ss' (iproute2) not found, needed to pick free ports"

    mkdir -p "$dir" || skip "cannot create $dir"
    dir=$(cd "$dir" && pwd -P)
    # a previous `up` in the same DIR must not leave daemons behind
    cmd_down "$dir"
    mkdir -p "$dir"/{etc,state,spool,log,run,munge} || skip "cannot create dirs under $dir"
    # munged insists: no group/other write on its dirs (and no group/other read on key)
    chmod 700 "$dir"/{state,spool,log,run}
    chmod 755 "$dir/etc"              # slurm.conf must be readable by any submitting user
    chmod 755 "$dir" "$dir/munge"   # socket dir must be traversable by job users
    rm -f "$dir"/log/*.log

    local host node ncpu ctld_port slurmd_port conf
    host=$(hostname -s 2>/dev/null || hostname)
    [ -n "$host" ] || host=localhost
    node=$host
    ncpu=$(nproc)
    ctld_port=${SLURM_ONE_NODE_CTLD_PORT:-$(pick_port 16817)} || skip "no free TCP port"
    slurmd_port=${SLURM_ONE_NODE_SLURMD_PORT:-$(pick_port $((ctld_port + 1)) "$ctld_port")} || skip "no free TCP port"
    conf=$dir/etc/slurm.conf

    # ---- munge ---------------------------------------------------------------
    local auth_lines
    if [ "$auth" = munge ]; then
        local sock=$dir/munge/munge.socket
        if [ ! -s "$dir/munge/munge.key" ]; then
            ( umask 077; dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none ) \
                || skip "cannot create munge key"
        fi
        chmod 600 "$dir/munge/munge.key"
        rm -f "$sock" "$sock.lock"
        # -f: munged refuses some setups (e.g. running as root, /tmp paths) without it
        munged -f --key-file="$dir/munge/munge.key" --socket="$sock" \
            --pid-file="$dir/run/munged.pid" --log-file="$dir/log/munged.log" \
            --seed-file="$dir/munge/munged.seed" >"$dir/log/munged.stderr" 2>&1 \
            || { tail_log "$dir/log/munged.stderr" "$dir/log/munged.log"; cmd_down "$dir"; skip "munged failed to start$(why "$dir/log/munged.stderr" "$dir/log/munged.log") (log: $dir/log/munged.log)"; }
        for b in $(seq 1 50); do [ -S "$sock" ] && break; sleep 0.1; done
        [ -S "$sock" ] || { cmd_down "$dir"; skip "munged socket $sock did not appear"; }
        auth_lines="AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sock"
    elif [ "$auth" = none ]; then
        auth_lines="AuthType=auth/none
CredType=cred/none"
    else
        die "SLURM_ONE_NODE_AUTH must be munge or none"
    fi

    # ---- slurm.conf ----------------------------------------------------------
    cat >"$conf" <<EOF
# generated by $PROG for a private one-node test cluster
ClusterName=onenode
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
$auth_lines
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
MailProg=/bin/true
SwitchType=switch/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SchedulerType=sched/backfill
MaxArraySize=10001
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
KillWait=5
Waittime=0
NodeName=$node NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$ncpu RealMemory=100 State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
EOF
    export SLURM_CONF=$conf

    # ---- slurmctld + slurmd (foreground mode, detached with setsid) ---------------
    # -D keeps them in the foreground so their stderr goes to our files; -c/-i: fresh state
    setsid slurmctld -D -c -i -f "$conf" </dev/null >"$dir/log/slurmctld.stderr" 2>&1 &
    echo $! >"$dir/run/slurmctld.pid"
    setsid slurmd -D -N "$node" -f "$conf" </dev/null >"$dir/log/slurmd.stderr" 2>&1 &
    echo $! >"$dir/run/slurmd.pid"

    # ---- wait for the node to be idle ------------------------------------------
    local t0 state="" now
    t0=$(date +%s)
    while :; do
        state=$(sinfo -h -N -n "$node" -o '%t' 2>/dev/null | head -n1)
        [ "$state" = idle ] && break
        now=$(date +%s)
        if ! pid_alive "$(cat "$dir/run/slurmctld.pid" 2>/dev/null)"; then
            tail_log "$dir/log/slurmctld.stderr"
            cmd_down "$dir"; skip "slurmctld died at startup$(why "$dir/log/slurmctld.log" "$dir/log/slurmctld.stderr") (log: $dir/log/slurmctld.log)"
        fi
        if ! pid_alive "$(cat "$dir/run/slurmd.pid" 2>/dev/null)"; then
            tail_log "$dir/log/slurmd.stderr"
            cmd_down "$dir"; skip "slurmd died at startup$(why "$dir/log/slurmd.log" "$dir/log/slurmd.stderr") (log: $dir/log/slurmd.log)"
        fi
        if [ $((now - t0)) -ge "$timeout" ]; then
            tail_log "$dir/log/slurmctld.log" "$dir/log/slurmd.log"
            cmd_down "$dir"; skip "node '$node' not idle after ${timeout}s (state: '${state:-none}'$(why "$dir/log/slurmd.log" "$dir/log/slurmctld.log")) (logs: $dir/log)"
        fi
        sleep 0.5
    done

    {
        echo "export SLURM_CONF=$conf"
    } >"$dir/env.sh"
    cat "$dir/env.sh"
    echo "$PROG: node '$node' idle after $(( $(date +%s) - t0 ))s (ctld port $ctld_port, slurmd port $slurmd_port, auth $auth)" >&2
    return 0
}

case ${1:-} in
    up)   [ $# -eq 2 ] || die "usage: $PROG up DIR";   cmd_up "$2" ;;
    down) [ $# -eq 2 ] || die "usage: $PROG down DIR"; cmd_down "$(cd "$2" 2>/dev/null && pwd -P || echo "$2")" ;;
    *)    die "usage: $PROG up|down DIR" ;;
esac

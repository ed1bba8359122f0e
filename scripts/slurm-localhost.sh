#!/usr/bin/env bash
# A one-node SLURM cluster on this machine (for `make test-cluster`): Debian's slurm-wlm + munge, 2 CPUs,
# partition "debug", job accounting through slurmdbd on a local MariaDB (so that sacct shows the jobs;
# squeue keeps finished jobs for an hour: MinJobAge). Needs root. Idempotent: installs what is missing,
# rewrites the configs, (re)starts the daemons.
#   scripts/slurm-localhost.sh          # up
#   scripts/slurm-localhost.sh down     # stop the daemons
set -euo pipefail
CPUS=${SLURM_LOCAL_CPUS:-2}
conf=/etc/slurm/slurm.conf
host=$(hostname -s)

stop() {
  for d in slurmd slurmctld slurmdbd munged; do
    if pid=$(pgrep -x "$d"); then kill $pid; fi
  done
}
if [ "${1:-up}" = down ]; then stop; exit 0; fi
[ "$(id -u)" = 0 ] || { echo "error: scripts/slurm-localhost.sh needs root (apt-get, daemons)" >&2; exit 1; }

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null || ! command -v slurmdbd >/dev/null \
  || ! command -v mariadbd >/dev/null; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm slurmdbd munge mariadb-server >/dev/null
fi

# munge: a key and a running daemon (authenticates slurmctld <-> slurmd <-> clients)
if [ ! -s /etc/munge/munge.key ]; then
  dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
fi
chown munge:munge /etc/munge/munge.key && chmod 0400 /etc/munge/munge.key
mkdir -p /run/munge /var/log/munge /var/lib/munge && chown munge:munge /run/munge /var/log/munge /var/lib/munge
pgrep -x munged >/dev/null || runuser -u munge -- /usr/sbin/munged --force

# accounting: MariaDB (local socket) <- slurmdbd <- slurmctld
mkdir -p /run/mysqld && chown mysql:mysql /run/mysqld
if ! pgrep -x mariadbd >/dev/null; then
  (mysqld_safe >/dev/null 2>&1 &)
  for _ in $(seq 1 30); do mysqladmin ping >/dev/null 2>&1 && break; sleep 1; done
fi
mysql -e "CREATE DATABASE IF NOT EXISTS slurm_acct_db; CREATE USER IF NOT EXISTS 'slurm'@'localhost' IDENTIFIED BY 'rods';
          GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost'; FLUSH PRIVILEGES;"
mkdir -p /etc/slurm
cat > /etc/slurm/slurmdbd.conf <<CONF
AuthType=auth/munge
DbdHost=localhost
SlurmUser=root
StorageType=accounting_storage/mysql
StorageHost=localhost
StorageUser=slurm
StoragePass=rods
StorageLoc=slurm_acct_db
PidFile=/run/slurmdbd.pid
LogFile=/var/log/slurm/slurmdbd.log
CONF
chmod 0600 /etc/slurm/slurmdbd.conf
mkdir -p /var/log/slurm
if pid=$(pgrep -x slurmdbd); then kill $pid; sleep 1; fi
/usr/sbin/slurmdbd
for _ in $(seq 1 30); do sacctmgr -n list cluster >/dev/null 2>&1 && break; sleep 1; done

mem=$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)  # [MB] offered to jobs
mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
cat > "$conf" <<CONF
# written by rods/scripts/slurm-localhost.sh: one node, $CPUS CPUs, for tests
ClusterName=rods-local
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
JobAcctGatherType=jobacct_gather/linux
JobCompType=jobcomp/none
MinJobAge=3600
ReturnToService=2
SchedulerType=sched/backfill
NodeName=$host CPUs=$CPUS RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF

stop_slurm() { for d in slurmd slurmctld; do if pid=$(pgrep -x "$d"); then kill $pid; fi; done; sleep 1; }
stop_slurm
sacctmgr -i add cluster rods-local >/dev/null 2>&1 || true  # known to slurmdbd before slurmctld registers
/usr/sbin/slurmctld -i   # -i: ignore saved state that no longer matches the config
/usr/sbin/slurmd
for _ in $(seq 1 30); do
  if sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
    sinfo -o '%P %D %c %m %T'
    exit 0
  fi
  scontrol update nodename="$host" state=resume >/dev/null 2>&1 || true
  sleep 1
done
echo "error: the node did not come up; see /var/log/slurm/slurmctld.log and slurmd.log" >&2
sinfo >&2 || true
exit 1

#!/usr/bin/env bash
# fresh_machine_check.sh - run `make demo` or `make test` of one commit on a
# pristine Debian 12 chroot, the way a newcomer with nothing installed would:
# the proof that the README's two commands install what they need.
#
# Needs root and network access to the Debian mirror (the Makefile's `deps`
# installs). The first run builds the base system with debootstrap: a minimal
# Debian (--variant=minbase) with only git, make and ca-certificates, apt
# sources configured, apt lists empty; it is kept as a tarball for later runs.
set -euo pipefail

prog=$(basename "$0")

usage() {
    cat <<EOF
usage: $prog [-h] COMMAND [COMMIT]

Unpack a fresh copy of the base chroot, clone COMMIT of the repository into
/root/icerubble inside it and run \`cd /root/icerubble && make COMMAND\` there,
timed, under nice. Prints the exit code and the wall time of the whole check.

  COMMAND   a Makefile target a newcomer runs: demo or test
            (any other target is accepted with FRESH_ANY_TARGET=1)
  COMMIT    any commit-ish of the repository (default: HEAD of \$BRANCH)

Environment (defaults in brackets):
  REPO        the repository to clone from            [this script's checkout]
  BRANCH      branch whose HEAD is the default COMMIT [main]
  FRESH_DIR   working folder (~4 GB per check)        [/var/tmp/icerubble-fresh]
  BASE_TAR    pristine base chroot tarball            [\$FRESH_DIR/base.tar]
  RUN_DIR     chroot for this check                   [\$FRESH_DIR/run-COMMAND]
  LOG         log file (overwritten)                  [\$FRESH_DIR/COMMAND.log]
  NICE        niceness of the chroot command          [10]
  CHROOT_LANG LANG inside the chroot                  [C.UTF-8]

Each log line is prefixed with the seconds elapsed since the start, e.g.
"[  312s]". The chroot is left in place for inspection and replaced by the
next check of the same COMMAND; every mount is undone on exit, also on failure.

exit status: the exit status of \`make COMMAND\` (2 for a usage error,
1 when the check itself could not be set up).
EOF
}

die() { echo "$prog: error: $*" >&2; exit 1; }

while getopts ":h" opt; do
    case $opt in
        h) usage; exit 0 ;;
        *) usage >&2; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
if [ $# -lt 1 ] || [ $# -gt 2 ]; then usage >&2; exit 2; fi

CMD=$1
case $CMD in
    demo|test) ;;
    *) [ "${FRESH_ANY_TARGET:-0}" = 1 ] || { echo "$prog: COMMAND must be demo or test, not '$CMD'" >&2; usage >&2; exit 2; } ;;
esac
[[ $CMD =~ ^[A-Za-z0-9_.-]+$ ]] || { echo "$prog: bad target name '$CMD'" >&2; exit 2; }

REPO=${REPO:-$(git -C "$(dirname "$0")" rev-parse --show-toplevel)}
BRANCH=${BRANCH:-main}
FRESH_DIR=${FRESH_DIR:-/var/tmp/icerubble-fresh}
BASE_TAR=${BASE_TAR:-$FRESH_DIR/base.tar}
RUN_DIR=${RUN_DIR:-$FRESH_DIR/run-$CMD}
LOG=${LOG:-$FRESH_DIR/$CMD.log}
NICE=${NICE:-10}
CHROOT_LANG=${CHROOT_LANG:-C.UTF-8}
COMMIT=${2:-$BRANCH}

[ "$(id -u)" = 0 ] || die "must run as root (chroot, mount)"
for tool in git tar chroot mount umount findmnt; do
    command -v "$tool" >/dev/null || die "$tool not found"
done
make_base() {   # the newcomer's machine: Debian 12 with git and make, nothing else
    local dir=$FRESH_DIR/base
    echo "$prog: building the base system in $dir (once)"
    command -v debootstrap >/dev/null || { apt-get update -qq && apt-get install -y -qq debootstrap; }
    rm -rf --one-file-system "$dir"
    debootstrap --variant=minbase --include=git,make,ca-certificates bookworm "$dir" \
        http://deb.debian.org/debian > "$FRESH_DIR/debootstrap.log"
    rm -f "$dir/etc/apt/sources.list"
    cat > "$dir/etc/apt/sources.list.d/debian.sources" <<'SOURCES'
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SOURCES
    # package scripts must not start daemons inside the chroot
    printf '#!/bin/sh\nexit 101\n' > "$dir/usr/sbin/policy-rc.d"
    chmod +x "$dir/usr/sbin/policy-rc.d"
    rm -rf "$dir"/var/lib/apt/lists/*   # `make deps` must run apt-get update itself
    tar -C "$dir" --numeric-owner -cpf "$BASE_TAR" .
}
mkdir -p "$FRESH_DIR"
[ -f "$BASE_TAR" ] || make_base
git -C "$REPO" rev-parse --git-dir >/dev/null 2>&1 || die "$REPO is not a git repository"
SHA=$(git -C "$REPO" rev-parse --verify -q "$COMMIT^{commit}") || die "$COMMIT: no such commit in $REPO"

mkdir -p "$FRESH_DIR"
FRESH_DIR=$(cd "$FRESH_DIR" && pwd -P)
mkdir -p "$(dirname "$RUN_DIR")" "$(dirname "$LOG")"
RUN_DIR=$(cd "$(dirname "$RUN_DIR")" && pwd -P)/$(basename "$RUN_DIR")
SRC=$RUN_DIR.src.git            # bare repo holding only $SHA's history, bind-mounted read-only
SRC_IN=/mnt/icerubble.git       # where it appears inside the chroot
[ "$RUN_DIR" != / ] || die "RUN_DIR must not be /"

# Anything still mounted below RUN_DIR (a killed earlier check)? Never rm -rf over /dev.
mounted_below() { findmnt -rn -o TARGET | awk -v p="$1" 'index($0, p "/") == 1 || $0 == p'; }
if [ -n "$(mounted_below "$RUN_DIR")" ]; then
    die "something is still mounted under $RUN_DIR (an interrupted check?); unmount it first:
$(mounted_below "$RUN_DIR")"
fi

MOUNTS=()   # in mount order; undone in reverse
cleanup() {
    local rc=$? i m pid
    set +e
    # processes of ours still running inside the chroot (e.g. after Ctrl-C)
    for pid in $(ls /proc | grep -E '^[0-9]+$'); do
        [ "$(readlink "/proc/$pid/root" 2>/dev/null)" = "$RUN_DIR" ] && kill "$pid" 2>/dev/null
    done
    for ((i = ${#MOUNTS[@]} - 1; i >= 0; i--)); do
        m=${MOUNTS[i]}
        umount -R "$m" 2>/dev/null || { sleep 1; umount -R "$m"; } || umount -lR "$m" ||
            echo "$prog: warning: could not unmount $m" >&2
    done
    if [ -n "$(mounted_below "$RUN_DIR")" ]; then
        echo "$prog: warning: still mounted under $RUN_DIR:" >&2; mounted_below "$RUN_DIR" >&2
    else
        rm -rf --one-file-system "$SRC"
    fi
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP

bind() {    # bind SRC DST [ro]: recursive, slave so nothing propagates back to the host
    mkdir -p "$2"
    mount --rbind "$1" "$2"
    MOUNTS+=("$2")
    mount --make-rslave "$2"
    if [ "${3:-}" = ro ]; then mount -o remount,bind,ro "$2"; fi
}

t_start=$(date +%s)
echo "$prog: $CMD of $SHA ($COMMIT) from $REPO in $RUN_DIR, log $LOG"

# 1. a pristine copy of the base system
rm -rf --one-file-system "$RUN_DIR" "$SRC"
mkdir -p "$RUN_DIR"
tar -C "$RUN_DIR" --numeric-owner -xpf "$BASE_TAR"
cp -L /etc/resolv.conf "$RUN_DIR/etc/resolv.conf"

# 2. the commit alone (its history, one branch), nothing from the work tree
git init -q --bare "$SRC"
git -C "$REPO" push -q "$SRC" "$SHA:refs/heads/$BRANCH"
git -C "$SRC" symbolic-ref HEAD "refs/heads/$BRANCH"

# 3. mounts
bind /proc "$RUN_DIR/proc"
bind /sys "$RUN_DIR/sys"
bind /dev "$RUN_DIR/dev"          # recursive: /dev/pts and /dev/shm come along
bind "$SRC" "$RUN_DIR$SRC_IN" ro

# 4. clone and run, as root in a clean environment (nothing from the host's)
inner=$(cat <<EOF
set -u
cd /root
git clone -q $SRC_IN icerubble || exit 1
cd icerubble
[ "\$(git rev-parse HEAD)" = "$SHA" ] || { echo "clone is at \$(git rev-parse HEAD), not $SHA"; exit 1; }
echo "== clone: \$(git log -1 --format='%h %s')"
echo "== make $CMD (started \$(date -u +%FT%TZ))"
TIMEFORMAT='== time make $CMD: real %0R s (%lR), user %0U s, sys %0S s'
time make $CMD
rc=\$?
echo "== make $CMD exit code \$rc"
exit \$rc
EOF
)

stamp() {   # prefix each line with the seconds since the check started
    local line
    while IFS= read -r line || [ -n "$line" ]; do
        printf '[%6ds] %s\n' "$(( $(date +%s) - t_start ))" "$line"
    done
}

set +e
nice -n "$NICE" chroot "$RUN_DIR" /usr/bin/env -i \
    HOME=/root USER=root LOGNAME=root SHELL=/bin/bash TERM=dumb LANG="$CHROOT_LANG" \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    PYTHONUNBUFFERED=1 \
    /bin/bash -c "$inner" </dev/null 2>&1 | stamp | tee "$LOG"
rc=${PIPESTATUS[0]}
set -e

t_end=$(date +%s)
wall=$((t_end - t_start))

# Phases, from the recipe lines make echoes: deps until the first `cmake -S`,
# build until the first `/usr/bin/python3` recipe, then the run itself.
ts_of() { grep -m1 -E "^\[ *[0-9]+s\] $1" "$LOG" | sed -E 's/^\[ *([0-9]+)s\].*/\1/'; }
t_make=$(ts_of '== make ') || true
t_cmake=$(ts_of 'cmake -S ') || true
t_run=$(ts_of '/usr/bin/python3 ') || true
{
    echo "== summary: make $CMD of $SHA"
    echo "==   exit code: $rc"
    printf '==   wall time of the whole check: %dm%02ds (%d s)\n' $((wall / 60)) $((wall % 60)) "$wall"
    if [ -n "$t_make" ] && [ -n "$t_cmake" ]; then
        echo "==   setup (unpack, clone):        ${t_make} s"
        echo "==   deps (apt-get):               $((t_cmake - t_make)) s"
        if [ -n "$t_run" ]; then
            echo "==   build (cmake):                $((t_run - t_cmake)) s"
            echo "==   run ($CMD):                   $((wall - t_run)) s"
        else
            echo "==   build (cmake), to the end:    $((wall - t_cmake)) s (no run started)"
        fi
    elif [ -n "$t_make" ]; then
        echo "==   setup (unpack, clone):        ${t_make} s"
        echo "==   deps (apt-get), to the end:   $((wall - t_make)) s (no build started)"
    fi
} | tee -a "$LOG"
exit "$rc"

#!/usr/bin/env bash
# The fresh-machine stage: the README's two commands on a minimal Debian 12
# with nothing installed by hand. A green CI on a used machine proves nothing
# about a fresh one (a hand-installed package once hid 12 failing tests).
#
#   1. mmdebstrap --variant=minbase bookworm (the tool's default mirror);
#   2. the committed tree (HEAD of this checkout) cloned into it, alone (the
#      package reads nothing outside itself: no ../shared beside it),
#      /etc/resolv.conf and /etc/hosts copied in;
#   3. the two commands run there with chroot, from a private mount and PID
#      namespace that mounts /proc and binds /sys and /dev: no mount reaches
#      the host, none outlives the namespace, no process outlives its PID 1;
#   4. the tree removed on every exit path (success, failure, timeout, signal),
#      never across a mount (rm --one-file-system).
#
# Usage: bash scripts/fresh_check.sh [--keep]   (needs root; --keep leaves the
# tree for a post-mortem, its path printed). AF_FRESH_TIMEOUT_S bounds the two
# commands (default 3600 s). Exits non-zero when either command fails.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
timeout_s=${AF_FRESH_TIMEOUT_S:-3600}
keep=0
[ "${1:-}" = "--keep" ] && keep=1
[ "$(id -u)" -eq 0 ] || {
  echo "fresh_check: needs root (mmdebstrap, chroot, mounts)" >&2
  exit 2
}
export PATH=/usr/bin:/usr/sbin:/bin:/sbin:$PATH
command -v mmdebstrap >/dev/null || bash "$root/scripts/setup.sh"

# The README's two commands, exactly as the README gives them.
commands=("bash scripts/run.sh" "bash scripts/test.sh")
for c in "${commands[@]}"; do
  grep -qE "^$c( |\$)" "$root/README.md" || {
    echo "fresh_check: README.md does not give the command '$c' at the start of a line" >&2
    exit 2
  }
done

work=$(mktemp -d /var/tmp/af_fresh.XXXXXX)
sys=$work/debian
cleanup() {
  local rc=$?
  trap - EXIT INT TERM HUP
  if [ "$keep" = 1 ]; then
    echo "fresh_check: kept $work"
  elif [ -d "$work" ]; then
    # The namespace took its mounts with it; --one-file-system still guards
    # against any that did not.
    rm -rf --one-file-system "$work" || echo "fresh_check: could not remove $work" >&2
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP

t0=$(date +%s)
echo "fresh_check: bootstrapping a minimal Debian 12 in $sys"
mmdebstrap --quiet --variant=minbase bookworm "$sys" >"$work/mmdebstrap.log" 2>&1 || {
  cat "$work/mmdebstrap.log" >&2
  echo "fresh_check: mmdebstrap failed" >&2
  exit 1
}
t1=$(date +%s)
echo "fresh_check: bootstrap $((t1 - t0)) s"

mkdir -p "$sys/work"
git clone -q "$root" "$sys/work/main"
git -C "$sys/work/main" log -1 --format='fresh_check: tree %h %s'
cp /etc/resolv.conf /etc/hosts "$sys/etc/"

# Inside: the namespace's PID 1 mounts what the chroot needs, then runs the
# two commands one after the other as a newcomer would, each timed.
inside=$(
  cat <<EOF
set -eu
mount -t proc proc "$sys/proc"
mount --rbind /sys "$sys/sys"
mount --rbind /dev "$sys/dev"
for c in "${commands[0]}" "${commands[1]}"; do
  s=\$(date +%s)
  echo "fresh_check: running '\$c'"
  if ! chroot "$sys" /usr/bin/env -i HOME=/root LANG=C.UTF-8 TERM=dumb CI=\${CI:-} \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    bash -c "cd /work/main && \$c"; then
    echo "fresh_check: '\$c' FAILED on the fresh system after \$((\$(date +%s) - s)) s"
    exit 1
  fi
  echo "fresh_check: '\$c' passed in \$((\$(date +%s) - s)) s"
done
EOF
)
status=0
timeout --kill-after=30 "$timeout_s" \
  unshare --mount --propagation private --pid --fork bash -c "$inside" || status=$?
t2=$(date +%s)
if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
  echo "fresh_check: the two commands did not finish within $timeout_s s"
fi
echo "fresh_check: stage $((t2 - t0)) s (bootstrap $((t1 - t0)) s, the two commands $((t2 - t1)) s)," \
  "$([ "$status" -eq 0 ] && echo passed || echo "FAILED ($status)")"
exit "$status"

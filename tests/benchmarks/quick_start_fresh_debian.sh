#!/usr/bin/env bash
# Times README's first command on a fresh Debian 12: a minimal debootstrap root, the
# repository's HEAD cloned into it, then each step of the command's && chain in order,
# as written, with the load average beside each. Run as root on a Debian host:
#
#   tests/benchmarks/quick_start_fresh_debian.sh [ROOT]
#
# ROOT (default: a new folder under /var/tmp) receives the fresh system, about 2 GB; it
# is left in place for inspection. Git and its certificates are installed before the
# clock starts (a user who cloned has them), and apt's lists are emptied, so `apt-get
# update` starts from nothing. The timings go to stdout, one line per step, then the
# whole.
set -euo pipefail

repo=$(git -C "$(dirname "$0")" rev-parse --show-toplevel)
root=${1:-$(mktemp -d /var/tmp/ringtol-fresh.XXXXXX)}
mirror=http://deb.debian.org/debian

command -v debootstrap >/dev/null || apt-get install -y debootstrap >/dev/null
# The README's first command: the first line of its first sh block.
quick_start=$(awk '/^```sh$/ { getline; print; exit }' "$repo/README.md")

debootstrap --variant=minbase bookworm "$root" "$mirror" >/dev/null
printf '%s\n' "deb $mirror bookworm main" "deb $mirror bookworm-updates main" \
  "deb http://deb.debian.org/debian-security bookworm-security main" >"$root/etc/apt/sources.list"
cp /etc/resolv.conf "$root/etc/resolv.conf"

cleanup() { umount -R "$root/dev" "$root/sys" "$root/proc" "$root/mnt" 2>/dev/null || true; }
trap cleanup EXIT
mount -t proc proc "$root/proc"
mount -t sysfs sys "$root/sys"
mount --rbind /dev "$root/dev" && mount --make-rslave "$root/dev"
mount --bind -o ro "$repo" "$root/mnt"
chroot "$root" bash -c 'apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -qq -y git ca-certificates \
  >/dev/null && git clone -q /mnt /root/ringtol && apt-get clean && rm -rf /var/lib/apt/lists/*'
umount "$root/mnt"

# Each && step in turn, in one shell, so a step sees what the earlier ones set.
printf '%s\n' "$quick_start" | sed 's/ && /\n/g' >"$root/root/quick_start_steps"
cat >"$root/root/time_steps.sh" <<'STEPS'
cd /root/ringtol
now() { date +%s.%N; }
start=$(now)
while IFS= read -r step; do
  t0=$(now)
  bash -c "$step" >/dev/null 2>/root/step.err || { echo "failed: $step"; cat /root/step.err; exit 1; }
  awk -v a="$t0" -v b="$(now)" -v load="$(cut -d' ' -f1-3 /proc/loadavg)" -v step="${step:0:70}" \
    'BEGIN { printf "%7.1f s  load %s  %s\n", b - a, load, step }'
done </root/quick_start_steps
awk -v a="$start" -v b="$(now)" 'BEGIN { printf "%7.1f s  whole\n", b - a }'
STEPS
echo "nproc $(nproc); commit $(git -C "$repo" rev-parse --short HEAD)"
chroot "$root" bash /root/time_steps.sh

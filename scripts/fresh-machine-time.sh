#!/usr/bin/env bash
# Times the README's `./run.sh main` on a fresh Debian 12 system (issue 34, item 5): a minimal
# bookworm (debootstrap --variant=minbase, 88 packages: no compiler, no CMake, no library of the
# project) is made in a scratch directory, a clean clone of this repository's HEAD is put in it,
# and `./run.sh main` runs there under chroot, installing everything with apt from the same
# Debian mirror as this machine. Same kernel and processor as the host, so the figure is this
# machine's as a fresh install would see it. Prints the phases and the total; docs/building.md
# holds the measured figure.
#
#   sudo scripts/fresh-machine-time.sh [SCRATCH_DIR]     (root: debootstrap, mount, chroot)
#
# Needs debootstrap (installed here when missing) and the network to the Debian mirror. Pause
# long background jobs first: the figure is the machine's, not the machine's leftover.
# The phases come from file times: apt ends when the build tree's CMakeCache.txt appears, the
# build when build/cli/ricochet is linked, the main job when run.sh returns.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
[ "$(id -u)" -eq 0 ] || { echo "fresh-machine-time: run as root (debootstrap, chroot)" >&2; exit 2; }
SCRATCH=${1:-$(mktemp -d /tmp/fresh-debian12-XXXX)}
MIRROR=${DEBIAN_MIRROR:-http://deb.debian.org/debian}
command -v debootstrap > /dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap

# shellcheck disable=SC2317  # run by the EXIT trap
cleanup() {
  # Unmount before anything is removed: the chroot's /dev, /proc and /sys are the host's.
  umount -R "$SCRATCH/proc" "$SCRATCH/sys" "$SCRATCH/dev" 2> /dev/null || true
  if mount | grep -q " $SCRATCH/"; then
    echo "fresh-machine-time: $SCRATCH still has mounts; not removed" >&2
  else
    rm -rf "$SCRATCH"
  fi
}
trap cleanup EXIT

echo "== debootstrap bookworm (minbase) into $SCRATCH" >&2
debootstrap --variant=minbase bookworm "$SCRATCH" "$MIRROR" > "$SCRATCH.debootstrap.log" 2>&1
cp /etc/resolv.conf "$SCRATCH/etc/"
if [ -f /etc/apt/sources.list.d/debian.sources ]; then
  cp /etc/apt/sources.list.d/debian.sources "$SCRATCH/etc/apt/sources.list.d/"
  rm -f "$SCRATCH/etc/apt/sources.list"
fi
mount -t proc proc "$SCRATCH/proc"
mount --rbind /sys "$SCRATCH/sys"
mount --rbind /dev "$SCRATCH/dev"
git clone -q "$ROOT" "$SCRATCH/root/ricochet"
echo "== ./run.sh main in the fresh system (clone of $(git -C "$ROOT" rev-parse --short HEAD))" >&2
start=$(date +%s.%N)
rc=0
chroot "$SCRATCH" /usr/bin/env -i HOME=/root LANG=C.UTF-8 \
  PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
  bash -c 'cd /root/ricochet && ./run.sh main' > "$SCRATCH.main.log" 2>&1 || rc=$?
end=$(date +%s.%N)
tree=$SCRATCH/root/ricochet
t_apt=$(stat -c %.Y "$tree/build/CMakeCache.txt" 2> /dev/null || echo "$end")
t_build=$(stat -c %.Y "$tree/build/cli/ricochet" 2> /dev/null || echo "$end")
packages=$(chroot "$SCRATCH" dpkg-query -W -f='.\n' | wc -l)
awk -v s="$start" -v a="$t_apt" -v b="$t_build" -v e="$end" -v rc="$rc" -v p="$packages" 'BEGIN {
  printf "status %d; packages installed at the end: %d\n", rc, p
  printf "apt (update, download, install)  %6.0f s\n", a - s
  printf "configure and build the program  %6.0f s\n", b - a
  printf "main job                         %6.0f s\n", e - b
  printf "total ./run.sh main              %6.0f s (%d min %02d s)\n", e - s, int((e - s) / 60), int(e - s) % 60
}'
echo "log: $SCRATCH.main.log" >&2
exit "$rc"

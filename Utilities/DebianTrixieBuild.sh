#!/usr/bin/env bash
# CI's second configuration: builds FFDShapeMatching and runs its whole test suite on Debian 13 (trixie: ITK 5.4.3,
# VTK 9.3, GCC 14, CMake 3.31), inside a chroot made on this Debian machine. Runs by hand too (as root):
#   bash Utilities/DebianTrixieBuild.sh
# The root file system is made once with debootstrap into a cache folder (FFD_TRIXIE_ROOT, default
# /var/cache/ffdshapematching/trixie-root) and reused while it is complete; its packages are installed by the
# module's own Utilities/InstallDependencies.sh, which knows trixie's names. The source tree is bind-mounted
# read-only at /src; the build (FFD_TRIXIE_BUILD, default /var/tmp/ffd-build inside the chroot) and ccache's cache
# stay in the root file system, so that a second run only rebuilds what changed. Inside, the README's test command
# runs: ./quickstart.sh test (stand-alone mode: Debian 13's ITK ships no module scripts either). The mirror is
# the one this machine's apt uses (FFD_DEBIAN_MIRROR overrides it).
# Exit status: that of the test command, 1 if the build printed a compiler warning, 2 when the chroot cannot be
# made.
set -euo pipefail
cd "$(dirname "$0")/.."
source_dir=$PWD

if [ "$(id -u)" -ne 0 ]; then
  echo "error: the Debian 13 chroot needs root (debootstrap, mount, chroot)" >&2
  exit 2
fi
root=${FFD_TRIXIE_ROOT:-/var/cache/ffdshapematching/trixie-root}
build=${FFD_TRIXIE_BUILD:-/var/tmp/ffd-build}
start=$(date +%s)

mirror=${FFD_DEBIAN_MIRROR:-}
if [ -z "$mirror" ]; then
  # The first Debian archive this machine's apt reads (deb822 "URIs:" or one-line "deb URL suite").
  mirror=$(cat /etc/apt/sources.list.d/*.sources 2>/dev/null | awk '/^URIs:/ && $2 !~ /security/ { print $2; exit }')
  if [ -z "$mirror" ]; then
    mirror=$(awk '$1 == "deb" && $3 !~ /security/ { print $2; exit }' /etc/apt/sources.list 2>/dev/null || true)
  fi
fi
if [ -z "$mirror" ]; then
  echo "error: no Debian mirror found in /etc/apt; set FFD_DEBIAN_MIRROR" >&2
  exit 2
fi

if [ ! -f "$root/.ffd-debootstrap-complete" ]; then
  if ! command -v debootstrap >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends debootstrap
  fi
  echo "== making the Debian 13 root file system in $root (from $mirror) =="
  rm -rf "$root"
  mkdir -p "$(dirname "$root")"
  if ! debootstrap --variant=minbase --include=ca-certificates trixie "$root" "$mirror" >"$root.debootstrap.log" 2>&1; then
    tail -n 20 "$root.debootstrap.log" >&2
    echo "error: debootstrap of trixie into $root failed (log: $root.debootstrap.log)" >&2
    exit 2
  fi
  # Services must not start inside the chroot while packages are installed.
  printf '#!/bin/sh\nexit 101\n' >"$root/usr/sbin/policy-rc.d"
  chmod +x "$root/usr/sbin/policy-rc.d"
  touch "$root/.ffd-debootstrap-complete"
  echo "== root file system made in $(($(date +%s) - start)) s =="
fi

mounts=()
cleanup() {
  local i
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do
    umount -l "${mounts[$i]}" 2>/dev/null || true
  done
}
trap cleanup EXIT
bind() { # bind SOURCE TARGET [ro|rec]
  mkdir -p "$2"
  if [ "${3:-}" = rec ]; then
    mount --rbind "$1" "$2"
    mount --make-rslave "$2"
  else
    mount --bind "$1" "$2"
  fi
  mounts+=("$2")
  if [ "${3:-}" = ro ]; then
    mount -o remount,bind,ro "$2"
  fi
}
# The root folder bound onto itself is a mount point of its own, so that tests that make private mount namespaces
# inside the chroot (unshare -m, as the full-file-system output-safety test does) can change its propagation.
bind "$root" "$root"
bind /proc "$root/proc"
# /sys with what is mounted below it: Slurm 24's slurmd (the workflow's Slurm test) needs /sys/fs/cgroup.
bind /sys "$root/sys" rec
bind /dev "$root/dev"
bind /dev/pts "$root/dev/pts"
mkdir -p "$root/dev/shm"
mount -t tmpfs tmpfs "$root/dev/shm"
mounts+=("$root/dev/shm")
bind "$source_dir" "$root/src" ro
# The host's name resolution: the workflow's Slurm test runs its controller on this host's name.
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
cp /etc/hosts "$root/etc/hosts" 2>/dev/null || true

in_chroot() {
  chroot "$root" /usr/bin/env -i HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    LANG=C.UTF-8 CCACHE_DIR=/var/cache/ccache CCACHE_BASEDIR=/src CCACHE_MAXSIZE=5G "$@"
}

echo "== Debian 13 packages (Utilities/InstallDependencies.sh inside the chroot) =="
in_chroot bash /src/Utilities/InstallDependencies.sh
in_chroot sh -c 'echo "ITK $(dpkg-query -W -f="\${Version}" libinsighttoolkit5-dev), VTK $(dpkg-query -W -f="\${Version}" libvtk9-dev), $(g++ --version | head -n 1), $(cmake --version | head -n 1)"'
echo "== packages ready at $(($(date +%s) - start)) s =="

echo "== build and whole test suite on Debian 13: ./quickstart.sh test =="
log=$(mktemp)
set +e
in_chroot env FFD_BUILD_DIR="$build" bash /src/quickstart.sh test 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
set -e
# No compiler warning may come from the module's code, including warnings GCC reports inside a system header for
# code inlined from the module's (ccache replays the warnings of cached objects, so a warm build counts them too).
warnings=$(grep -c -E '(^|[[:space:]])(/src/|/usr/include/).*warning:' "$log" || true)
if [ "$warnings" -gt 0 ]; then
  echo "== $warnings compiler warning(s) in the Debian 13 build: =="
  grep -B4 -E '(^|[[:space:]])(/src/|/usr/include/).*warning:' "$log" | head -n 60
  [ "$status" -ne 0 ] || status=1
fi
rm -f "$log"
echo "== Debian 13 configuration ended with status $status in $(($(date +%s) - start)) s =="
exit "$status"

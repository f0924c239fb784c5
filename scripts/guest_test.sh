#!/usr/bin/env bash
# Runs a test suite inside Debian's own kernel, booted by qemu, for the parts of hal that need
# kernel features this host may lack (AF_CAN and vcan; dummy_hcd and FunctionFS) or hardware
# it does not have (a UART: the 8250 driver on qemu's 16550A).
#
#   scripts/guest_test.sh [SUITE]        SUITE: can (default), usb or uart
#
# Environment: BUILD (build directory, default ./build; the suite's test programs are taken
# from its tests/ folder), QEMU, BUSYBOX, GUEST_TIMEOUT (seconds, default 240), GUEST_KERNEL_PACKAGE
# (default: what linux-image-amd64 depends on).
#
# The kernel package is fetched once with `apt-get download` (not installed) and unpacked into
# $BUILD/guest/kernel; delete that folder to take a newer one. Each run builds a small
# initramfs (static busybox, the suite's modules with their dependencies, the test binary with
# its shared libraries), boots it with KVM when /dev/kvm opens (else software emulation), and
# reads the guest's console: exit 0 when the suite passed with no test skipped, 1 when it
# failed, 77 (skip) when qemu, a static busybox or the kernel package cannot be had.
set -euo pipefail

skip() {
  echo "guest_test: SKIP: $*" >&2
  exit 77
}
fail() {
  echo "guest_test: FAIL: $*" >&2
  exit 1
}

SOURCE=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD=${BUILD:-$SOURCE/build}
BUILD=$(cd "$BUILD" && pwd) || fail "no build directory '$BUILD'"
SUITE=${1:-can}
GUEST_TIMEOUT=${GUEST_TIMEOUT:-240}
BUSYBOX=${BUSYBOX:-/usr/bin/busybox}
QEMU=${QEMU:-qemu-system-x86_64}
CACHE=$BUILD/guest
GUEST_DIR=$SOURCE/tests/guest

# Per suite: the modules to load (their dependencies come along), the project's programs (built
# targets, under /opt/sculpt/ in the guest) and host programs (under /opt/host/) to copy in
# with their libraries; and the devices qemu adds for it.
DEVICES=()
case "$SUITE" in
  can)
    MODULES=(vcan can-raw)
    TARGETS=(hal_tests)
    PROGRAMS=(ip) # iproute2's: busybox's ip cannot create a vcan link
    ;;
  usb)
    MODULES=(dummy_hcd usb_f_fs)
    TARGETS=(guest_usb_tests ffs_glove)
    PROGRAMS=()
    ;;
  uart) # the 8250 driver is built into Debian's kernel (its console is one)
    MODULES=(xhci-pci ftdi_sio)
    TARGETS=(guest_uart_tests)
    PROGRAMS=()
    # ttyS0 the console (as -nographic alone gives it); ttyS1 on nothing (the tests loop it
    # back); ttyS2 wired to an emulated FTDI USB-serial adapter (ttyUSB0) through a socket
    # whose two ends are both qemu's: a cable between a UART and a USB-serial adapter.
    LINK_SOCKET=$CACHE/uart-link.sock
    rm -f "$LINK_SOCKET"
    DEVICES=(-serial mon:stdio -serial null
      -chardev "socket,id=link,path=$LINK_SOCKET,server=on,wait=off" -serial chardev:link
      -chardev "socket,id=adapter,path=$LINK_SOCKET" -device qemu-xhci -device usb-serial,chardev=adapter)
    ;;
  *) fail "unknown suite '$SUITE' (can, usb, uart)" ;;
esac
[ -f "$GUEST_DIR/$SUITE.sh" ] || fail "no $GUEST_DIR/$SUITE.sh"

command -v "$QEMU" >/dev/null || skip "$QEMU not found (Debian package qemu-system-x86)"
[ -x "$BUSYBOX" ] || skip "no busybox at $BUSYBOX (Debian package busybox-static)"
if ldd "$BUSYBOX" >/dev/null 2>&1; then
  skip "$BUSYBOX is linked dynamically; the guest needs a static one (Debian package busybox-static)"
fi
for target in "${TARGETS[@]}"; do
  [ -x "$BUILD/tests/$target" ] || fail "no $BUILD/tests/$target (build the target $target first)"
done

# --- the kernel: fetched and unpacked once, under a lock (suites may run in parallel) ---------
mkdir -p "$CACHE"
KERNEL=$CACHE/kernel
fetch_kernel() {
  command -v apt-get >/dev/null || skip "no apt-get to fetch Debian's kernel package"
  command -v dpkg-deb >/dev/null || skip "no dpkg-deb to unpack Debian's kernel package"
  local pkg=${GUEST_KERNEL_PACKAGE:-}
  if [ -z "$pkg" ]; then
    pkg=$(apt-cache depends linux-image-amd64 2>/dev/null |
      sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*-amd64\)$/\1/p' | head -n 1)
  fi
  [ -n "$pkg" ] || skip "apt-cache knows no linux-image-amd64 (apt-get update?)"
  local tmp=$KERNEL.tmp
  rm -rf "$tmp"
  mkdir -p "$tmp"
  echo "guest_test: fetching $pkg (once; cached in $KERNEL)" >&2
  if ! (cd "$tmp" && apt-get download "$pkg") >"$tmp/download.log" 2>&1; then
    sed 's/^/  /' "$tmp/download.log" >&2
    skip "apt-get download $pkg failed"
  fi
  dpkg-deb -x "$tmp"/*.deb "$tmp/root" || fail "dpkg-deb could not unpack $tmp/*.deb"
  rm -f "$tmp"/*.deb
  local version
  version=$(ls "$tmp/root/lib/modules")
  [ -f "$tmp/root/boot/vmlinuz-$version" ] || fail "$pkg has no boot/vmlinuz-$version"
  # The package leaves modules.dep to the installer's depmod; busybox's does the same job.
  "$BUSYBOX" depmod -b "$tmp/root" "$version" || fail "depmod failed on $pkg's modules"
  echo "$pkg $version" >"$tmp/ready"
  rm -rf "$KERNEL"
  mv "$tmp" "$KERNEL"
}
exec 9>"$CACHE/lock"
flock 9
[ -f "$KERNEL/ready" ] || fetch_kernel
flock -u 9
read -r KERNEL_PACKAGE KERNEL_VERSION <"$KERNEL/ready"
MODDIR=$KERNEL/root/lib/modules/$KERNEL_VERSION

# --- the modules, dependencies first (modules.dep lists each module's path and its deps) ------
declare -A seen=()
ORDERED=()
module_path() { # name (dashes and underscores alike) -> path relative to MODDIR
  local pattern=${1//[-_]/[-_]}
  grep -o -m 1 -E "^([^:]*/)?${pattern}\.ko(\.xz|\.zst)?:" "$MODDIR/modules.dep" | sed 's/:$//'
}
add_module() { # path relative to MODDIR
  local path=$1 dep
  [ -z "${seen[$path]:-}" ] || return 0
  seen[$path]=1
  for dep in $(grep -m 1 -F "$path:" "$MODDIR/modules.dep" | cut -d: -f2); do
    add_module "$dep"
  done
  ORDERED+=("$path")
}
for name in ${MODULES[@]+"${MODULES[@]}"}; do
  path=$(module_path "$name") || fail "$KERNEL_PACKAGE has no module $name"
  add_module "$path"
done

# --- the initramfs ------------------------------------------------------------------------------
# A dynamically linked program with its shared libraries and the dynamic loader, at the paths
# ldd names.
copy_program() { # host path, guest path
  local lib libs
  mkdir -p "$ROOT$(dirname "$2")"
  cp -L "$1" "$ROOT$2"
  libs=$(ldd "$1" | awk '/=> \// { print $3 } /^\t\// { print $1 }') || fail "ldd $1 failed"
  for lib in $libs; do
    [ -e "$ROOT$lib" ] && continue
    mkdir -p "$ROOT$(dirname "$lib")"
    cp -L "$lib" "$ROOT$lib"
  done
}
ROOT=$CACHE/root-$SUITE
INITRD=$CACHE/initrd-$SUITE.gz
build_initrd() { # the folder holding the suite's built targets
  local path program host_path target
  rm -rf "$ROOT"
  mkdir -p "$ROOT"/{bin,dev,proc,sys,tmp,etc,opt/sculpt}
  cp "$BUSYBOX" "$ROOT/bin/busybox"
  install -m 755 "$GUEST_DIR/init" "$ROOT/init"
  cp "$GUEST_DIR/$SUITE.sh" "$ROOT/etc/guest-suite.sh"
  : >"$ROOT/etc/guest-modules"
  for path in "${ORDERED[@]}"; do
    mkdir -p "$ROOT/lib/modules/$KERNEL_VERSION/$(dirname "$path")"
    cp "$MODDIR/$path" "$ROOT/lib/modules/$KERNEL_VERSION/$path"
    echo "/lib/modules/$KERNEL_VERSION/$path" >>"$ROOT/etc/guest-modules"
  done
  for target in "${TARGETS[@]}"; do
    copy_program "$1/$target" "/opt/sculpt/$target"
  done
  for program in ${PROGRAMS[@]+"${PROGRAMS[@]}"}; do
    host_path=$(command -v "$program") || skip "no $program on this host to copy into the guest"
    copy_program "$host_path" "/opt/host/$program"
  done
  (cd "$ROOT" && find . | "$BUSYBOX" cpio -o -H newc 2>/dev/null) | gzip -1 >"$INITRD"
}

# Software emulation cannot run a binary built for this machine's CPU (SCULPT_NATIVE: qemu's
# "max" CPU has AVX2 but no AVX-512), so under it the guest gets the suite's programs from a
# portable build of their own, kept in $CACHE/portable (configured once, then rebuilt
# incrementally), a unity build as the test command's later passes are (scripts/test.sh). Prints
# the folder holding them.
portable_targets() {
  local portable=$CACHE/portable flags
  if ! grep -q '^SCULPT_NATIVE:BOOL=ON' "$BUILD/CMakeCache.txt" 2>/dev/null; then
    echo "$BUILD/tests"
    return
  fi
  flags=$(sed -n 's/^CMAKE_CXX_FLAGS:STRING=//p' "$BUILD/CMakeCache.txt")
  echo "guest_test: building a portable ${TARGETS[*]} (SCULPT_NATIVE=OFF) in $portable" >&2
  if [ ! -f "$portable/build.ninja" ]; then
    cmake -S "$SOURCE" -B "$portable" -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=$flags" \
      -DSCULPT_NATIVE=OFF -DSCULPT_BUILD_BENCHMARKS=OFF -DCMAKE_UNITY_BUILD=ON >"$CACHE/portable.log" 2>&1 ||
      fail "configuring the portable build failed (see $CACHE/portable.log)"
  fi
  cmake --build "$portable" -j "${GUEST_BUILD_JOBS:-2}" --target "${TARGETS[@]}" >>"$CACHE/portable.log" 2>&1 ||
    fail "building the portable ${TARGETS[*]} failed (see $CACHE/portable.log)"
  echo "$portable/tests"
}

# --- boot ---------------------------------------------------------------------------------------
LOG=$CACHE/console-$SUITE.log
# boot ACCEL_OPTIONS...: runs qemu in the background writing the console to $LOG; sets QEMU_PID.
boot() {
  : >"$LOG"
  timeout "$GUEST_TIMEOUT" "$QEMU" "$@" ${DEVICES[@]+"${DEVICES[@]}"} -smp 1 -m 1G -nographic -no-reboot -nic none \
    -kernel "$KERNEL/root/boot/vmlinuz-$KERNEL_VERSION" -initrd "$INITRD" \
    -append "console=ttyS0 quiet loglevel=3 panic=-1" </dev/null >"$LOG" 2>&1 &
  QEMU_PID=$!
}
# waits up to $1 s for the guest's init to say it started; 1 if it did not.
booted_within() {
  local deadline=$((SECONDS + $1))
  while [ "$SECONDS" -lt "$deadline" ]; do
    grep -q '^GUEST-INIT' "$LOG" && return 0
    kill -0 "$QEMU_PID" 2>/dev/null || return 1
    sleep 0.2
  done
  return 1
}
start=$SECONDS
ACCEL_NAME=
# Nested under some hypervisors (this project's own machines among them) a KVM guest crawls
# so slowly that it does not reach the kernel's first message in minutes. The verdict is kept
# per host kernel in $CACHE/kvm-stalls (delete it to try KVM again).
KVM_VERDICT=$CACHE/kvm-stalls
if [ "$(cat "$KVM_VERDICT" 2>/dev/null)" != "$(uname -r)" ] && { exec 8<>/dev/kvm; } 2>/dev/null; then
  exec 8>&-
  echo "guest_test: booting $KERNEL_PACKAGE ($KERNEL_VERSION) with KVM, suite '$SUITE'" >&2
  build_initrd "$BUILD/tests"
  boot -enable-kvm -cpu host
  if booted_within "${GUEST_KVM_BOOT_TIMEOUT:-15}"; then
    ACCEL_NAME=KVM
  else
    kill "$QEMU_PID" 2>/dev/null || true
    wait "$QEMU_PID" 2>/dev/null || true
    uname -r >"$KVM_VERDICT"
    echo "guest_test: the KVM guest did not reach its init in ${GUEST_KVM_BOOT_TIMEOUT:-15} s; using software emulation" >&2
  fi
fi
if [ -z "$ACCEL_NAME" ]; then
  ACCEL_NAME="software emulation (TCG)"
  [ ! -f "$KVM_VERDICT" ] || echo "guest_test: KVM stalls on this host ($KVM_VERDICT)" >&2
  programs=$(portable_targets)
  build_initrd "$programs"
  echo "guest_test: booting $KERNEL_PACKAGE ($KERNEL_VERSION) with $ACCEL_NAME, suite '$SUITE'" >&2
  boot -accel tcg -cpu max
fi
set +e
wait "$QEMU_PID"
qemu_rc=$?
set -e
elapsed=$((SECONDS - start))
tr -d '\r' <"$LOG" >"$LOG.txt" && mv "$LOG.txt" "$LOG"
cat "$LOG"
echo "guest_test: the guest ran for ${elapsed} s ($ACCEL_NAME)" >&2

[ "$qemu_rc" -ne 124 ] || fail "the guest did not power off within $GUEST_TIMEOUT s (console: $LOG)"
[ "$qemu_rc" -eq 0 ] || fail "qemu exited with status $qemu_rc (console: $LOG)"
grep -q '^GUEST-RESULT rc=' "$LOG" || fail "the guest printed no result line (console: $LOG)"
# gtest names each skipped test twice: where it ran and in the closing list.
skipped=$({ grep '^\[  SKIPPED \] [^0-9]' "$LOG" || true; } | sort -u | wc -l)
[ "$skipped" -eq 0 ] || fail "$skipped test(s) skipped inside the guest; they must run there"
grep -q '^GUEST-RESULT rc=0$' "$LOG" || fail "the suite failed inside the guest (console: $LOG)"
passed=$(sed -n 's/^\[  PASSED  \] \([0-9]*\) tests\?\.$/\1/p' "$LOG" | tail -n 1)
[ -n "$passed" ] && [ "$passed" -gt 0 ] || fail "no test passed inside the guest (console: $LOG)"
echo "guest_test: suite '$SUITE' passed in the guest: $passed tests, none skipped, ${elapsed} s ($ACCEL_NAME)" >&2

#!/usr/bin/env bash
# Install everything glovesculpt needs on Debian 12 (bookworm), then fetch the
# real 3D scans into data/scans/ (scripts/fetch_scans.sh).
#
# Idempotent: when every package is already installed it runs no apt-get at all
# (not even `apt-get update`) and only re-checks the scans, so re-runs are fast.
# Non-interactive (fine with CI=true and no stdin); works from any cwd; as root,
# or as a user with sudo.
set -euo pipefail

SCRIPT_DIR="$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)"
ROOT="$(cd -- "$SCRIPT_DIR/.." && pwd -P)"

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libnanoflann-dev libqhull-dev
  liblcm-dev liblcm-bin libglib2.0-dev
  libusb-1.0-0-dev
  libtomlplusplus-dev libcli11-dev libspdlog-dev libstb-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  can-utils
  libcgal-demo zlib1g-dev
  libosmesa6-dev libglfw3-dev libgl-dev xvfb xdotool
  clang-format clang-tidy clang libclang-rt-14-dev
  openjdk-17-jdk-headless liblcm-java libjchart2d-java python3-matplotlib
  gnuplot-nox
  qemu-system-x86 busybox-static iproute2 xz-utils
  python3
)

log() { printf 'setup: %s\n' "$*"; }
die() { printf 'setup: FAILED: %s\n' "$*" >&2; exit 1; }

if [[ -r /etc/os-release ]]; then
  # shellcheck disable=SC1091
  . /etc/os-release
  if [[ "${ID:-}" != debian || "${VERSION_ID:-}" != 12 ]]; then
    log "warning: written for Debian 12, this is ${PRETTY_NAME:-unknown}; trying anyway"
  fi
fi
command -v dpkg-query >/dev/null 2>&1 || die "dpkg-query not found: this script needs Debian (apt/dpkg)"

installed() { # installed PKG -> 0 if dpkg has it fully installed
  [[ "$(dpkg-query -W -f='${db:Status-Abbrev}' "$1" 2>/dev/null)" == "ii "* ]]
}

missing=()
for p in "${PACKAGES[@]}"; do
  installed "$p" || missing+=("$p")
done

# Node.js + npm. On these machines `nodejs` comes from NodeSource and bundles npm;
# Debian's `npm` package conflicts with it, so only ask apt for npm when there is none.
if ! command -v npm >/dev/null 2>&1; then
  if installed nodejs && [[ "$(dpkg-query -W -f='${Version}' nodejs)" == *nodesource* ]]; then
    die "nodejs from NodeSource is installed but 'npm' is not on PATH; Debian's npm conflicts with it. Reinstall NodeSource nodejs (it bundles npm) or fix PATH."
  fi
  missing+=(nodejs npm)
elif ! command -v node >/dev/null 2>&1; then
  missing+=(nodejs)
fi

if ((${#missing[@]})); then
  SUDO=()
  if ((EUID != 0)); then
    command -v sudo >/dev/null 2>&1 \
      || die "not root and no sudo; cannot install: ${missing[*]}"
    if [[ -t 0 ]]; then SUDO=(sudo); else SUDO=(sudo -n); fi
  fi
  apt_get() {
    "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get -y -qq \
      -o Dpkg::Use-Pty=0 -o DPkg::Lock::Timeout=300 "$@"
  }
  log "installing ${#missing[@]} missing package(s): ${missing[*]}"
  log "apt-get update"
  apt_get update || die "apt-get update failed"
  log "apt-get install"
  apt_get install "${missing[@]}" >/dev/null || die "apt-get install failed for: ${missing[*]}"
  still=()
  for p in "${missing[@]}"; do installed "$p" || still+=("$p"); done
  ((${#still[@]} == 0)) || die "packages still not installed after apt-get: ${still[*]}"
  log "installed: ${missing[*]}"
else
  log "all ${#PACKAGES[@]} Debian packages + node $(node --version) / npm $(npm --version 2>/dev/null) already installed; skipping apt-get"
fi

command -v node >/dev/null 2>&1 || die "'node' still not on PATH after installing nodejs"
command -v npm  >/dev/null 2>&1 || die "'npm' still not on PATH after installing npm"

log "fetching scans into data/scans/"
bash "$SCRIPT_DIR/fetch_scans.sh" || die "scripts/fetch_scans.sh failed (see message above)"
log "done (repo: $ROOT)"

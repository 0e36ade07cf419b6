#!/usr/bin/env bash
# Installs the Debian packages odocal needs. Idempotent: packages already present are skipped,
# and apt is only asked when something is missing. Run as root (CI) or with sudo.
#
#   ./toolchain/install-deps.sh          everything: host tests, STM32F4 image + QEMU, Linux board
#   ./toolchain/install-deps.sh --demo   only what `cmake --build --preset host --target odocal`
#                                        needs (host compiler, CMake, Ninja, Eigen, JSON, CLI11, fmt)
set -euo pipefail

# The `odocal` host program: compiler, build tools and the libraries it links.
demo_packages=(
  build-essential cmake ninja-build
  libeigen3-dev nlohmann-json3-dev libcli11-dev libfmt-dev
)
# Everything else CI builds and runs.
other_packages=(
  python3 clang clang-format libclang-rt-14-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib libnewlib-arm-none-eabi binutils-arm-none-eabi
  qemu-system-arm qemu-system-x86 busybox-static xz-utils
  libgpiod-dev gpiod
  chromium fonts-liberation
  gcc-aarch64-linux-gnu g++-aarch64-linux-gnu libgpiod-dev:arm64
)

packages=("${demo_packages[@]}")
case "${1:-}" in
  --demo) ;;
  "") packages+=("${other_packages[@]}") ;;
  *)
    echo "usage: $0 [--demo]" >&2
    exit 2
    ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
# The Raspberry Pi (aarch64) build links Debian's arm64 libraries: enable that architecture.
if printf '%s\n' "${missing[@]}" | grep -q ':arm64$' &&
  ! dpkg --print-foreign-architectures | grep -qx arm64; then
  "${sudo_cmd[@]}" dpkg --add-architecture arm64
fi
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" apt-get update -q
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"

#!/usr/bin/env bash
# Runs the Linux backend against a real kernel GPIO device.
#
#   run-vm-test.sh TEST_PROGRAM WORK_DIR [ODOCAL_LINUX]
#
# This machine's kernel has no GPIO, so the test boots one: Debian's amd64 kernel (looked up
# with apt-cache, fetched with apt-get download), with gpio-mockup and irq_sim built out of tree
# from Debian's kernel source and headers, in QEMU (TCG) with a busybox-static initramfs that
# runs TEST_PROGRAM (statically linked). The guest prints "ODOCAL-VM-RESULT: PASS|FAIL".
# With ODOCAL_LINUX (a static odocal-linux) the guest also runs the robot process on the mockup
# chips with a scripted console and prints "ODOCAL-LINUX-RESULT: PASS|FAIL".
#
# The kernel image and the two modules are cached per kernel ABI in
#   ${ODOCAL_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/odocal}/linux-vm/<abi>/
# Exit status: 0 pass, 1 fail, 77 skipped (a Debian package could not be fetched).
set -euo pipefail

readonly skip_status=77
program=${1:?usage: run-vm-test.sh TEST_PROGRAM WORK_DIR}
work=${2:?usage: run-vm-test.sh TEST_PROGRAM WORK_DIR}
robot_program=${3:-}
cache_root=${ODOCAL_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/odocal}/linux-vm

log() { echo "vm-test: $*"; }
fail() {
  echo "vm-test: FAIL: $*"
  exit 1
}
skip() {
  echo "vm-test: SKIP: $*"
  exit "${skip_status}"
}

for tool in qemu-system-x86_64 busybox apt-cache apt-get dpkg-deb make gzip flock timeout; do
  command -v "${tool}" > /dev/null ||
    fail "${tool} not found (toolchain/install-deps.sh installs qemu-system-x86, busybox-static)"
done
busybox_bin=$(command -v busybox)
# ldd fails on a static executable: the initramfs has no libc for a dynamic one.
if ldd "${busybox_bin}" > /dev/null 2>&1; then
  fail "${busybox_bin} is dynamically linked: install busybox-static"
fi
[ -x "${program}" ] || fail "test program ${program} not built"

# --- 1. Which kernel: the one Debian's amd64 meta-package points at today. -----------------
lookup_abi() {
  apt-cache depends linux-image-amd64 2> /dev/null |
    sed -n 's/^ *Depends: linux-image-\([0-9][^ ]*-amd64\)$/\1/p' | head -n 1
}
abi=$(lookup_abi || true)
if [ -z "${abi}" ] && [ "$(id -u)" -eq 0 ]; then
  log "apt-cache knows no linux-image-amd64: running apt-get update once"
  apt-get update -q > /dev/null 2>&1 || true
  abi=$(lookup_abi || true)
fi
if [ -z "${abi}" ]; then
  # Offline: use the newest kernel already built, if any.
  abi=$(ls -1 "${cache_root}" 2> /dev/null | grep -- '-amd64$' | sort -V | tail -n 1 || true)
  [ -n "${abi}" ] || skip "cannot look up Debian's kernel: apt-cache has no linux-image-amd64"
  log "kernel lookup failed; using cached ${abi}"
fi
cache=${cache_root}/${abi}
mkdir -p "${cache}"

# --- 2. Kernel image and modules, built once per ABI. ----------------------------------------
build_kernel_pieces() {
  local version headers_deps common kbuild source_pkg tmp root src
  version=$(apt-cache show --no-all-versions "linux-image-${abi}" 2> /dev/null |
    sed -n 's/^Version: //p' | head -n 1)
  [ -n "${version}" ] || skip "apt-cache has no version for linux-image-${abi}"
  headers_deps=$(apt-cache depends "linux-headers-${abi}" 2> /dev/null)
  common=$(sed -n 's/^ *Depends: \(linux-headers-[^ ]*-common\)$/\1/p' <<< "${headers_deps}" |
    head -n 1)
  kbuild=$(sed -n 's/^ *Depends: \(linux-kbuild-[0-9.]*\)$/\1/p' <<< "${headers_deps}" |
    head -n 1)
  [ -n "${common}" ] && [ -n "${kbuild}" ] ||
    skip "apt-cache cannot resolve the headers of linux-headers-${abi}"
  source_pkg=linux-source-${kbuild#linux-kbuild-}
  log "kernel ${abi} (${version}): fetching image, ${source_pkg}, headers, ${kbuild}"

  tmp=${cache}/tmp
  rm -rf "${tmp}"
  mkdir -p "${tmp}/debs"
  # apt-get download runs as the _apt user when it can; let it write here.
  chmod 0777 "${tmp}/debs" 2> /dev/null || true
  local pkg
  for pkg in "linux-image-${abi}=${version}" "linux-headers-${abi}=${version}" \
    "${common}=${version}" "${kbuild}=${version}" "${source_pkg}=${version}"; do
    if ! (cd "${tmp}/debs" && apt-get download -q "${pkg}" > /dev/null 2>&1); then
      # The source may trail or lead the image by a Debian revision; any 6.x.y source of the
      # same series has the same two files.
      if [ "${pkg%%=*}" = "${source_pkg}" ] &&
        (cd "${tmp}/debs" && apt-get download -q "${source_pkg}" > /dev/null 2>&1); then
        log "${source_pkg}=${version} unavailable; using the candidate version"
        continue
      fi
      rm -rf "${tmp}"
      skip "cannot fetch Debian package ${pkg} (apt-get download failed)"
    fi
  done

  root=${tmp}/root
  mkdir -p "${root}"
  for pkg in "${tmp}"/debs/linux-headers-*.deb "${tmp}"/debs/linux-kbuild-*.deb; do
    dpkg-deb -x "${pkg}" "${root}"
  done
  dpkg-deb --fsys-tarfile "${tmp}"/debs/linux-image-*.deb |
    tar -x -C "${root}" --wildcards './boot/vmlinuz-*'
  dpkg-deb --fsys-tarfile "${tmp}"/debs/linux-source-*.deb |
    tar -x -C "${root}" --wildcards './usr/src/linux-source-*.tar.xz'
  src=${tmp}/src
  mkdir -p "${src}"
  tar -xJf "${root}"/usr/src/linux-source-*.tar.xz -C "${src}" --strip-components=1 --wildcards \
    '*/drivers/gpio/gpio-mockup.c' '*/drivers/gpio/gpiolib.h' '*/kernel/irq/irq_sim.c'

  # The headers package includes its -common half by absolute path: point it here.
  local kdir=${root}/usr/src/linux-headers-${abi}
  sed -i "s#^include /usr/src/#include ${root}/usr/src/#" "${kdir}/Makefile"

  local mod=${tmp}/mod
  mkdir -p "${mod}"
  cp "${src}/drivers/gpio/gpio-mockup.c" "${src}/drivers/gpio/gpiolib.h" \
    "${src}/kernel/irq/irq_sim.c" "${mod}/"
  # irq_sim is built into kernels that need it, so it calls the unexported irq_to_desc();
  # as a module it must go through generic_handle_irq(), and it needs a licence tag.
  grep -q 'handle_simple_irq(irq_to_desc(irqnum))' "${mod}/irq_sim.c" ||
    fail "irq_sim.c of ${source_pkg} changed: the out-of-tree patch no longer applies"
  sed -i 's/handle_simple_irq(irq_to_desc(irqnum))/generic_handle_irq(irqnum)/' "${mod}/irq_sim.c"
  printf '\n#include <linux/module.h>\nMODULE_LICENSE("GPL");\n' >> "${mod}/irq_sim.c"
  echo 'obj-m += irq_sim.o gpio-mockup.o' > "${mod}/Kbuild"
  log "building irq_sim.ko and gpio-mockup.ko out of tree"
  make -s -C "${kdir}" M="${mod}" modules -j2 > "${tmp}/build.log" 2>&1 ||
    {
      tail -n 30 "${tmp}/build.log"
      fail "out-of-tree build of gpio-mockup failed (log above)"
    }

  cp "${root}"/boot/vmlinuz-* "${cache}/vmlinuz"
  cp "${mod}/irq_sim.ko" "${mod}/gpio-mockup.ko" "${cache}/"
  echo "${version}" > "${cache}/version"
  rm -rf "${tmp}"
}

exec 9> "${cache_root}/.lock"
flock 9
if [ ! -s "${cache}/vmlinuz" ] || [ ! -s "${cache}/gpio-mockup.ko" ] ||
  [ ! -s "${cache}/irq_sim.ko" ]; then
  build_kernel_pieces
else
  log "kernel ${abi} ($(cat "${cache}/version" 2> /dev/null)) and modules cached in ${cache}"
fi
flock -u 9

# --- 3. The initramfs: busybox, the two modules, the test program, an init script. -----------
rm -rf "${work}/initramfs"
mkdir -p "${work}/initramfs"/{bin,dev,proc,sys,tmp,lib/modules}
cp "${busybox_bin}" "${work}/initramfs/bin/busybox"
cp "${cache}/irq_sim.ko" "${cache}/gpio-mockup.ko" "${work}/initramfs/lib/modules/"
cp "${program}" "${work}/initramfs/bin/odocal-vmtest"
if [ -n "${robot_program}" ]; then
  [ -x "${robot_program}" ] || fail "odocal-linux ${robot_program} not built"
  cp "${robot_program}" "${work}/initramfs/bin/odocal-linux"
  # The mockup has no PWM chip: left_pwm falls back to software PWM, right_pwm is software only.
  cat > "${work}/initramfs/odocal-linux.conf" << 'EOF'
chip = gpiochip0
left_a = 0
left_b = 1
right_a = 2
right_b = 3
left_dir = 4
right_dir = 5
enable = 6
left_pwm = pwmchip0:0
left_pwm_gpio = 7
right_pwm = none
right_pwm_gpio = gpiochip1:0
store = /tmp/params.bin
EOF
fi
cat > "${work}/initramfs/init" << 'EOF'
#!/bin/busybox sh
/bin/busybox --install -s /bin
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t debugfs debugfs /sys/kernel/debug
if insmod /lib/modules/irq_sim.ko &&
  insmod /lib/modules/gpio-mockup.ko gpio_mockup_ranges=-1,8,-1,4; then
  echo "guest: kernel $(uname -r), chips: $(ls /dev | grep gpiochip | tr '\n' ' ')"
  /bin/odocal-vmtest
  status=$?
  [ "$status" -eq 0 ] || echo "guest: test program exited with status $status"
  if [ -x /bin/odocal-linux ]; then
    # The robot process with a scripted console: saved parameters survive a restart.
    printf 'set c_l 1.01\nsave\nstatus\n' |
      /bin/odocal-linux --config /odocal-linux.conf > /tmp/run1.txt 2> /tmp/err1.txt
    first=$?
    printf 'get c_l\nstatus\n' |
      /bin/odocal-linux --config /odocal-linux.conf > /tmp/run2.txt 2> /tmp/err2.txt
    second=$?
    # ROSArduinoBridge's commands with diffdrive_arduino's bytes (each line ended by a bare CR):
    # one reply each in that firmware's format, no echo (docs/ros.md).
    printf '\re\rm 10 10\ru 30:20:0:100\rb\rx\rm 0 0\rr\re\r' |
      /bin/odocal-linux --config /odocal-linux.conf > /tmp/run3.txt 2> /tmp/err3.txt
    third=$?
    printf 'Invalid Command\n0 0\nOK\nOK\n115200\nOK\nOK\nOK\n0 0\n' > /tmp/want3.txt
    grep -v '^#' /tmp/run3.txt | tr -d '\r' > /tmp/got3.txt
    cat /tmp/err1.txt /tmp/run1.txt /tmp/run2.txt /tmp/run3.txt
    if [ "$third" -eq 0 ] && cmp -s /tmp/want3.txt /tmp/got3.txt; then
      echo "guest: ROSArduinoBridge commands answered"
    else
      echo "guest: ROSArduinoBridge commands NOT answered as expected (exit $third)"
      third=1
    fi
    if [ "$first" -eq 0 ] && [ "$second" -eq 0 ] && [ "$third" -eq 0 ] &&
      grep -q '^ok .*tick_rt=1 .*pwm=software_low_precision' /tmp/run1.txt &&
      grep -q 'software PWM' /tmp/err1.txt && grep -q '^ok .*1\.01' /tmp/run2.txt; then
      echo "ODOCAL-LINUX-RESULT: PASS"
    else
      echo "ODOCAL-LINUX-RESULT: FAIL (exit $first/$second/$third)"
    fi
  fi
else
  echo "ODOCAL-VM-RESULT: FAIL (the gpio-mockup modules did not load)"
fi
poweroff -f
EOF
chmod +x "${work}/initramfs/init"
(cd "${work}/initramfs" && find . | busybox cpio -o -H newc 2> /dev/null | gzip -1) \
  > "${work}/initramfs.gz"

# --- 4. Boot. -----------------------------------------------------------------------------------
log "booting ${abi} in qemu-system-x86_64 (TCG)"
started=$(date +%s)
set +e
timeout 600 qemu-system-x86_64 -accel tcg -smp 1 -m 512 -display none -serial stdio \
  -monitor none -no-reboot -kernel "${cache}/vmlinuz" -initrd "${work}/initramfs.gz" \
  -append "console=ttyS0 quiet loglevel=3 panic=-1" < /dev/null 2>&1 | tr -d '\r' |
  tee "${work}/guest.log"
qemu_status=${PIPESTATUS[0]}
set -e
log "guest ran $(($(date +%s) - started)) s (qemu status ${qemu_status}); log in ${work}/guest.log"
if grep -q '^ODOCAL-VM-RESULT: PASS' "${work}/guest.log" &&
  { [ -z "${robot_program}" ] || grep -q '^ODOCAL-LINUX-RESULT: PASS' "${work}/guest.log"; }; then
  echo "vm-test: PASS"
  exit 0
fi
[ "${qemu_status}" -ne 124 ] || fail "the guest did not finish within 600 s"
grep -q '^ODOCAL-VM-RESULT:' "${work}/guest.log" || fail "the guest printed no result"
fail "checks failed in the guest (see the check and ODOCAL-* lines above)"

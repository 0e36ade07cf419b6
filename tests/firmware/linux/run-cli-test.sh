#!/usr/bin/env bash
# odocal-linux's command line and configuration errors, on a machine without GPIO chips:
# each case must exit with the documented status and a message naming the culprit.
#   run-cli-test.sh ODOCAL_LINUX WORK_DIR
set -uo pipefail
program=${1:?usage: run-cli-test.sh ODOCAL_LINUX WORK_DIR}
work=${2:?usage: run-cli-test.sh ODOCAL_LINUX WORK_DIR}
mkdir -p "${work}"
failures=0

# expect NAME STATUS TEXT ARGS...: runs the program, checks its exit status and that stderr or
# stdout contains TEXT.
expect() {
  local name=$1 status=$2 text=$3
  shift 3
  local output actual
  output=$("${program}" "$@" 2>&1)
  actual=$?
  if [ "${actual}" -eq "${status}" ] && grep -qF -- "${text}" <<< "${output}"; then
    echo "ok   ${name}: ${output%%$'\n'*}"
  else
    echo "FAIL ${name}: status ${actual} (want ${status}), output:"
    echo "${output}" | head -n 5
    failures=$((failures + 1))
  fi
}

good=${work}/good.conf
cat > "${good}" << 'EOF_CONF'
# a complete configuration
chip = gpiochip0
left_a = 17
left_b = 27
right_a = 22
right_b = 23
left_dir = 5
right_dir = 6
left_pwm = pwmchip0:0
right_pwm = pwmchip0:1
left_pwm_gpio = 12
right_pwm_gpio = 13
EOF_CONF

expect "help" 0 "left_pwm_gpio" --help
expect "unknown option" 2 '"--frobnicate"' --frobnicate
expect "stray argument" 2 'unknown option "extra"' extra
expect "option without its value" 2 "--store needs a value" --store
expect "pty and tty" 2 "--pty and --tty exclude each other" --pty --tty /dev/null
expect "version" 0 "odocal-linux " --version
expect "missing config" 2 "missing.conf" --config "${work}/missing.conf"
{ cat "${good}"; echo "speed = 3"; } > "${work}/key.conf"
expect "unknown key named with its line" 2 'key.conf:13: unknown key "speed"' --config "${work}/key.conf"
sed 's/^left_b = 27/left_b = 2x7/' "${good}" > "${work}/value.conf"
expect "bad value named" 2 'bad value "2x7" for "left_b"' --config "${work}/value.conf"
sed '/^right_b/d' "${good}" > "${work}/required.conf"
expect "missing key named" 2 'missing required key "right_b"' --config "${work}/required.conf"
sed 's/^right_dir = 6/right_dir = 17/' "${good}" > "${work}/twice.conf"
expect "line used twice named" 2 "left_a and right_dir both use gpiochip0 line 17" --config "${work}/twice.conf"
sed 's/^chip = gpiochip0/chip = gpiochip7/' "${good}" > "${work}/chip.conf"
expect "missing chip named" 1 'GPIO chip "gpiochip7" not found' --config "${work}/chip.conf"

# Numbers in the file: digits only, inside the documented range, both bounds included.
{ cat "${work}/chip.conf"; echo "event_priority = 99   # the highest SCHED_FIFO priority"; } > "${work}/top.conf"
expect "priority 99 taken (then the chip is missing)" 1 'GPIO chip "gpiochip7" not found' --config "${work}/top.conf"
{ cat "${good}"; echo "event_priority = 100"; } > "${work}/prio.conf"
expect "priority 100 refused" 2 'prio.conf:13: bad value "100" for "event_priority"' --config "${work}/prio.conf"
{ cat "${good}"; echo "pwm_hz = 18446744073709551616"; } > "${work}/wrap.conf"
expect "2^64 Hz refused, not wrapped" 2 'bad value "18446744073709551616" for "pwm_hz"' --config "${work}/wrap.conf"
{ cat "${good}"; echo "soft_pwm_hz = +200"; } > "${work}/sign.conf"
expect "a sign refused" 2 'bad value "+200" for "soft_pwm_hz"' --config "${work}/sign.conf"
{ cat "${good}"; echo "event_holdback_us = 1e3"; } > "${work}/exp.conf"
expect "an exponent refused" 2 'bad value "1e3" for "event_holdback_us"' --config "${work}/exp.conf"

if [ "${failures}" -ne 0 ]; then
  echo "FAIL: ${failures} case(s)"
  exit 1
fi
echo "PASS"

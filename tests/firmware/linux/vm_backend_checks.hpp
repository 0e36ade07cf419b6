// Checks of the Linux backend's parts on the mockup chips (vm_backend_checks.cpp).
#pragma once

namespace odocal::vm_test {

/// A missing chip, line or PWM chip, and a line in use (by another process or twice by this
/// one), are refused naming the line, its role and its owner.
void check_errors();
/// The software PWM's carrier and duty cycle, read back on a mockup line, and duty 0 and 1.
void check_software_pwm_duty();

}  // namespace odocal::vm_test

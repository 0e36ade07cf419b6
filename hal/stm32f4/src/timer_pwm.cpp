#include "odocal/hal/stm32f4/timer_pwm.hpp"

#include "odocal/hal/stm32f4/rcc.hpp"
#include "odocal/hal/stm32f4/tim.hpp"

namespace odocal::hal::stm32f4 {
namespace {

void enable_timer_clock(Block timer) {
  if (timer.base == tim::tim2.base) {
    rcc::apb1enr.set(rcc::apb1enr_tim2.mask());
  } else if (timer.base == tim::tim3.base) {
    rcc::apb1enr.set(rcc::apb1enr_tim3.mask());
  } else if (timer.base == tim::tim4.base) {
    rcc::apb1enr.set(rcc::apb1enr_tim4.mask());
  } else if (timer.base == tim::tim5.base) {
    rcc::apb1enr.set(rcc::apb1enr_tim5.mask());
  }
}

}  // namespace

void start_pwm_timer(const PwmTimerConfig& config) {
  const Block t = config.timer;
  enable_timer_clock(t);
  tim::psc(t).write(0u);
  tim::arr(t).write(pwm_steps(config) - 1u);
  tim::egr(t).write(tim::egr_ug.mask());  // load PSC, ARR and the CCR preloads
  tim::cr1(t).write(tim::cr1_arpe.mask() | tim::cr1_cen.mask());
}

void TimerPwm::start() {
  const Block t = config_.timer;
  enable_timer_clock(t);
  tim::ccr(t, channel_).write(0u);
  tim::ccmr(t, channel_).modify(tim::ccmr_ocm(channel_), tim::ocm_pwm1);
  tim::ccmr(t, channel_).set(tim::ccmr_ocpe(channel_).mask());
  tim::ccer(t).set(tim::ccer_cce(channel_).mask());
}

void TimerPwm::do_set_duty(float duty) {
  // duty is in [0, 1] (the interface clamps); CCR = steps means 100 %.
  const float steps = static_cast<float>(pwm_steps(config_));
  tim::ccr(config_.timer, channel_).write(static_cast<std::uint32_t>(duty * steps + 0.5f));
}

void force_pwm_zero(Block timer, std::uint8_t channel) {
  tim::ccr(timer, channel).write(0u);
}

}  // namespace odocal::hal::stm32f4

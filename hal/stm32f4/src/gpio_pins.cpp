#include "odocal/hal/stm32f4/gpio_pins.hpp"

#include "odocal/hal/stm32f4/exti.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/hal/stm32f4/irq.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"

namespace odocal::hal::stm32f4 {
namespace {

constexpr std::uint32_t exti_irq(std::uint8_t line) {
  if (line <= 4u) {
    return irq::exti0 + line;
  }
  return line <= 9u ? irq::exti9_5 : irq::exti15_10;
}

}  // namespace

void configure_pin(gpio::Pin pin, gpio::Mode mode, gpio::Pull pull, gpio::Speed speed,
                   std::uint8_t alternate_function) {
  rcc::ahb1enr.set(rcc::ahb1enr_gpio(static_cast<std::uint8_t>(pin.port)).mask());
  const gpio::Port port = pin.port;
  const Field two = gpio::two_bits(pin.number);
  gpio::otyper(port).clear(bit(pin.number).mask());  // push-pull
  gpio::ospeedr(port).modify(two, static_cast<std::uint32_t>(speed));
  gpio::pupdr(port).modify(two, static_cast<std::uint32_t>(pull));
  if (mode == gpio::Mode::alternate) {
    gpio::afr(pin).modify(gpio::af_field(pin.number), alternate_function);
  }
  gpio::moder(port).modify(two, static_cast<std::uint32_t>(mode));
}

void GpioOutput::start() {
  do_set(initial_);
  configure_pin(pin_, gpio::Mode::output);
}

void GpioOutput::do_set(bool level) {
  const std::uint32_t pin_bit = 1u << pin_.number;
  gpio::bsrr(pin_.port).write(level ? pin_bit : pin_bit << 16);
}

void start_exti_line(gpio::Pin pin, gpio::Pull pull, std::uint8_t priority) {
  configure_pin(pin, gpio::Mode::input, pull);
  rcc::apb2enr.set(rcc::apb2enr_syscfg.mask());
  const std::uint8_t line = pin.number;
  syscfg::exticr(line).modify(syscfg::exticr_field(line), static_cast<std::uint32_t>(pin.port));
  const std::uint32_t line_bit = 1u << line;
  exti::rtsr.set(line_bit);
  exti::ftsr.set(line_bit);
  exti::pr.write(line_bit);
  exti::imr.set(line_bit);
  enable_irq(exti_irq(line), priority);
}

}  // namespace odocal::hal::stm32f4

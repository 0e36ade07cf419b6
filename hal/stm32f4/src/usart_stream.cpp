#include "odocal/hal/stm32f4/usart_stream.hpp"

#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/hal/stm32f4/usart.hpp"

namespace odocal::hal::stm32f4 {

UsartStream::UsartStream(const UsartConfig& config) : config_(config) {}

void UsartStream::start() {
  const Block u = config_.usart;
  usart::cr1(u).write(0u);
  usart::cr2(u).write(0u);  // 1 stop bit
  usart::cr3(u).write(0u);
  usart::brr(u).write(usart::brr_value(config_.pclk_hz, config_.baud));
  attach_interrupt(exception_of_irq(config_.irq), &UsartStream::on_interrupt, this);
  usart::cr1(u).write(usart::cr1_ue.mask() | usart::cr1_te.mask() | usart::cr1_re.mask() |
                      usart::cr1_rxneie.mask());
  enable_irq(config_.irq, config_.priority);
}

void UsartStream::on_interrupt(void* self) {
  auto& stream = *static_cast<UsartStream*>(self);
  const Block u = stream.config_.usart;
  std::uint32_t status = usart::sr(u).read();
  if ((status & (usart::sr_rxne.mask() | usart::sr_ore.mask())) != 0u) {
    // Reading DR after SR clears RXNE and ORE.
    const auto byte = static_cast<std::uint8_t>(usart::dr(u).read());
    const bool overrun = (status & usart::sr_ore.mask()) != 0u;
    if (!stream.rx_.push(byte) || overrun) {
      // This handler is the only writer: a plain increment, no read-modify-write loop.
      stream.rx_dropped_.store(stream.rx_dropped_.load(std::memory_order_relaxed) + 1u,
                               std::memory_order_relaxed);
    }
  }
  // Only this handler writes CR1 after start(), so its read-modify-write cannot race.
  std::uint8_t byte = 0u;
  while ((usart::sr(u).read() & usart::sr_txe.mask()) != 0u && stream.tx_.pop(byte)) {
    usart::dr(u).write(byte);
  }
  if (stream.tx_.empty()) {
    usart::cr1(u).clear(usart::cr1_txeie.mask());
  } else {
    usart::cr1(u).set(usart::cr1_txeie.mask());
  }
}

std::size_t UsartStream::do_read(std::uint8_t* out, std::size_t capacity) {
  std::size_t n = 0u;
  while (n < capacity && rx_.pop(out[n])) {
    ++n;
  }
  return n;
}

std::size_t UsartStream::do_write(const std::uint8_t* data, std::size_t size) {
  std::size_t n = 0u;
  while (n < size && tx_.push(data[n])) {
    ++n;
  }
  if (n > 0u) {
    pend_irq(config_.irq);
  }
  return n;
}

void UsartStream::emergency_write(Block u, const char* text) {
  constexpr std::uint32_t max_polls = 100'000u;  // > 1 byte time at 115200 Bd and 168 MHz
  for (; *text != '\0'; ++text) {
    for (std::uint32_t i = 0u; i < max_polls; ++i) {
      if ((usart::sr(u).read() & usart::sr_txe.mask()) != 0u) {
        break;
      }
    }
    usart::dr(u).write(static_cast<std::uint8_t>(*text));
  }
}

}  // namespace odocal::hal::stm32f4

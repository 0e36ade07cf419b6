// The robot's encoder edge path (serve_encoder_edge, as board_robot.cpp wires it: port C, lines
// 0/1 and 2/3, TIM5 stamps) on fake registers: exactly the wheel's two pending bits cleared and
// nothing else touched, A and B from their own bits of one IDR read, the core's decoder counting
// a quadrature sequence up and down with the timer's stamps, and a missed edge counted illegal.

#include "odocal/hal/stm32f4/encoder_edge.hpp"

#include <gtest/gtest.h>

#include <cstdint>

#include "odocal/drive/quadrature_decoder.hpp"
#include "odocal/hal/stm32f4/exti.hpp"
#include "odocal/hal/stm32f4/gpio.hpp"
#include "odocal/hal/stm32f4/tim.hpp"
#include "register_fake.hpp"

namespace odocal::test {
namespace {

namespace f4 = hal::stm32f4;

// The robot board's wiring (firmware/stm32f4/board_robot.cpp, docs/wiring.md).
constexpr f4::gpio::Port encoder_port = f4::gpio::Port::c;
constexpr f4::Block stamp_timer = f4::tim::tim5;
const std::uintptr_t pr = f4::exti::pr.address;
const std::uintptr_t idr = f4::gpio::idr(encoder_port).address;
const std::uintptr_t cnt = f4::tim::cnt(stamp_timer).address;

/// Records what the edge path hands on.
struct RecordingSink {
  int calls = 0;
  bool a = false;
  bool b = false;
  std::uint32_t t_us = 0u;
  void on_edge(bool level_a, bool level_b, std::uint32_t now_us) {
    ++calls;
    a = level_a;
    b = level_b;
    t_us = now_us;
  }
};

void expect_access(const RegisterFake& bus, std::size_t i, bool write, std::uintptr_t address) {
  SCOPED_TRACE(testing::Message() << "access " << i);
  ASSERT_LT(i, bus.access_count());
  EXPECT_EQ(bus.access(i).write, write);
  EXPECT_EQ(bus.access(i).address, address);
}

TEST(EncoderEdge, ClearsExactlyTheWheelsTwoPendingBitsThenReadsIdrAndTimerOnce) {
  RegisterFake bus;
  RecordingSink sink;
  bus.set(pr, 0xFFFFu);  // every line pending: a read-modify-write would write the others back
  f4::serve_encoder_edge<0u, 1u>(bus, encoder_port, stamp_timer, sink);
  ASSERT_EQ(bus.access_count(), 3u);
  expect_access(bus, 0u, true, pr);
  EXPECT_EQ(bus.access(0u).value, 0b0011u);  // write 1 to clear lines 0 and 1 only
  expect_access(bus, 1u, false, idr);
  expect_access(bus, 2u, false, cnt);

  bus.clear_log();
  f4::serve_encoder_edge<2u, 3u>(bus, encoder_port, stamp_timer, sink);
  ASSERT_EQ(bus.access_count(), 3u);
  expect_access(bus, 0u, true, pr);
  EXPECT_EQ(bus.access(0u).value, 0b1100u);  // lines 2 and 3 only
  expect_access(bus, 1u, false, idr);
  expect_access(bus, 2u, false, cnt);
  EXPECT_EQ(sink.calls, 2);
  EXPECT_EQ(bus.overflows(), 0u);
}

TEST(EncoderEdge, TakesAAndBFromTheirOwnBitsOfTheOneIdrRead) {
  RegisterFake bus;
  RecordingSink sink;
  struct Case {
    std::uint32_t idr;
    bool a;
    bool b;
  };
  // Right wheel: A on pin 2, B on pin 3; the other pins (the left wheel's too) must not matter.
  const Case cases[] = {{0b0100u, true, false},       {0b1000u, false, true},
                        {0b1100u, true, true},        {0x0000u, false, false},
                        {0xFFFF'FFF3u, false, false}, {0xFFFF'FFF7u, true, false},
                        {0x0000'000Bu, false, true}};
  for (const Case& c : cases) {
    SCOPED_TRACE(testing::Message() << "IDR 0x" << std::hex << c.idr);
    bus.set(idr, c.idr);
    bus.set(cnt, c.idr ^ 0x5A5Au);
    bus.clear_log();
    f4::serve_encoder_edge<2u, 3u>(bus, encoder_port, stamp_timer, sink);
    EXPECT_EQ(sink.a, c.a);
    EXPECT_EQ(sink.b, c.b);
    EXPECT_EQ(sink.t_us, c.idr ^ 0x5A5Au);
    std::size_t idr_reads = 0u;
    for (std::size_t i = 0u; i < bus.access_count(); ++i) {
      idr_reads += !bus.access(i).write && bus.access(i).address == idr ? 1u : 0u;
    }
    EXPECT_EQ(idr_reads, 1u);
  }
}

/// IDR bits of the left wheel (A = pin 0, B = pin 1), with the right wheel's pins set to show
/// that they are ignored.
std::uint32_t left_levels(bool a, bool b) {
  return 0b1100u | (a ? 0b01u : 0u) | (b ? 0b10u : 0u);
}

TEST(EncoderEdge, CountsAQuadratureSequenceUpAndDownWithTheTimerStamps) {
  RegisterFake bus;
  drive::QuadratureDecoder decoder;
  decoder.reset(false, false);
  // Forward (A leads B): 00 -> A1B0 -> A1B1 -> A0B1 -> 00, twice: +8.
  const bool forward[4][2] = {{true, false}, {true, true}, {false, true}, {false, false}};
  std::uint32_t t_us = 1'000u;
  std::uint32_t expected = 0u;
  for (int edge = 0; edge < 8; ++edge) {
    bus.set(idr, left_levels(forward[edge % 4][0], forward[edge % 4][1]));
    t_us += 250u;
    bus.set(cnt, t_us);
    f4::serve_encoder_edge<0u, 1u>(bus, encoder_port, stamp_timer, decoder);
    ++expected;
    const drive::EncoderSnapshot s = decoder.snapshot();
    ASSERT_EQ(s.count, expected) << "forward edge " << edge;
    EXPECT_EQ(s.last_edge_us, t_us);
  }
  // Backward: the same states in reverse order, from 00: -3, back to 5.
  const bool backward[3][2] = {{false, true}, {true, true}, {true, false}};
  for (int edge = 0; edge < 3; ++edge) {
    bus.set(idr, left_levels(backward[edge][0], backward[edge][1]));
    t_us += 400u;
    bus.set(cnt, t_us);
    f4::serve_encoder_edge<0u, 1u>(bus, encoder_port, stamp_timer, decoder);
    --expected;
    const drive::EncoderSnapshot s = decoder.snapshot();
    ASSERT_EQ(s.count, expected) << "backward edge " << edge;
    EXPECT_EQ(s.last_edge_us, t_us);
  }
  const drive::EncoderSnapshot s = decoder.snapshot();
  EXPECT_EQ(s.count, 5u);
  EXPECT_EQ(s.edges, 11u);
  EXPECT_EQ(s.illegal, 0u);
}

TEST(EncoderEdge, BothChannelsChangingIsCountedIllegalAndLeavesThePosition) {
  RegisterFake bus;
  drive::QuadratureDecoder decoder;
  decoder.reset(false, false);
  bus.set(idr, left_levels(true, false));
  bus.set(cnt, 500u);
  f4::serve_encoder_edge<0u, 1u>(bus, encoder_port, stamp_timer, decoder);  // +1
  bus.set(idr, left_levels(false, true));                                   // A and B both flip
  bus.set(cnt, 900u);
  f4::serve_encoder_edge<0u, 1u>(bus, encoder_port, stamp_timer, decoder);
  const drive::EncoderSnapshot s = decoder.snapshot();
  EXPECT_EQ(s.illegal, 1u);
  EXPECT_EQ(s.count, 1u);
  EXPECT_EQ(s.edges, 1u);
  EXPECT_EQ(s.last_edge_us, 500u);  // the stamp of the last valid edge
}

}  // namespace
}  // namespace odocal::test

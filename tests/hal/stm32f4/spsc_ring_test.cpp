// hal/stm32f4's SpscRing (the USART's receive and transmit queues) on the host: order, full and
// empty, wrap of the free-running indices, and one producer thread against one consumer thread
// (the interrupt and the main loop on the robot).

#include "odocal/hal/stm32f4/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

namespace {

using odocal::hal::stm32f4::SpscRing;

TEST(Stm32f4SpscRing, HoldsExactlyItsCapacityInOrder) {
  SpscRing<8> ring;
  EXPECT_TRUE(ring.empty());
  for (std::uint8_t i = 0; i < 8u; ++i) {
    EXPECT_TRUE(ring.push(i));
  }
  EXPECT_FALSE(ring.push(99u));  // full: refused, nothing overwritten
  std::uint8_t byte = 0;
  for (std::uint8_t i = 0; i < 8u; ++i) {
    ASSERT_TRUE(ring.pop(byte));
    EXPECT_EQ(byte, i);
  }
  EXPECT_FALSE(ring.pop(byte));
  EXPECT_TRUE(ring.empty());
}

TEST(Stm32f4SpscRing, KeepsOrderAcrossManyWraps) {
  SpscRing<4> ring;
  std::uint8_t expected = 0;
  std::uint8_t next = 0;
  // 3 in, 2 out, repeated: the indices pass the capacity many times over.
  for (int round = 0; round < 1000; ++round) {
    for (int i = 0; i < 3 && ring.push(next); ++i) {
      ++next;
    }
    std::uint8_t byte = 0;
    for (int i = 0; i < 2 && ring.pop(byte); ++i) {
      ASSERT_EQ(byte, expected++);
    }
  }
}

TEST(Stm32f4SpscRing, OneProducerThreadAndOneConsumerThreadLoseAndReorderNothing) {
  static SpscRing<16> ring;
  constexpr std::uint32_t count = 200000;
  std::thread producer([] {
    for (std::uint32_t i = 0; i < count;) {
      if (ring.push(static_cast<std::uint8_t>(i * 7u))) {
        ++i;
      }
    }
  });
  std::uint32_t received = 0;
  std::uint32_t wrong = 0;
  while (received < count) {
    std::uint8_t byte = 0;
    if (ring.pop(byte)) {
      wrong += byte != static_cast<std::uint8_t>(received * 7u) ? 1u : 0u;
      ++received;
    }
  }
  producer.join();
  EXPECT_EQ(wrong, 0u);
  EXPECT_TRUE(ring.empty());
}

}  // namespace

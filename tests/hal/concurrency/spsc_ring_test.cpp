// The one SPSC byte ring (the console's receive ring, the STM32F4 USART's receive and transmit
// rings) on the host: order, full and empty, size and free space, peek, the wrap of the indices,
// and one producer thread against one consumer thread (the interrupt and the main loop).

#include "odocal/concurrency/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

namespace {

using odocal::concurrency::SpscRing;

TEST(SpscRing, HoldsCapacityLessOneInOrderAndRefusesWhenFull) {
  SpscRing<8> ring;
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.size(), 0u);
  EXPECT_EQ(ring.free_space(), 7u);
  for (std::uint8_t i = 0; i < 7u; ++i) {
    EXPECT_TRUE(ring.push(i));
    EXPECT_EQ(ring.size(), i + 1u);
  }
  EXPECT_FALSE(ring.push(99u));  // full: refused, nothing overwritten
  EXPECT_FALSE(ring.empty());
  EXPECT_EQ(ring.size(), 7u);
  EXPECT_EQ(ring.free_space(), 0u);
  std::uint8_t byte = 0;
  for (std::uint8_t i = 0; i < 7u; ++i) {
    ASSERT_TRUE(ring.pop(byte));
    EXPECT_EQ(byte, i);
  }
  EXPECT_FALSE(ring.pop(byte));
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.free_space(), 7u);
}

TEST(SpscRing, PeekShowsTheOldestByteWithoutRemovingIt) {
  SpscRing<4> ring{};  // zeroed: GCC cannot see that peek reads only slots a push wrote
  std::uint8_t byte = 0;
  EXPECT_FALSE(ring.peek(byte));
  ASSERT_TRUE(ring.push(10u));
  ASSERT_TRUE(ring.push(20u));
  ASSERT_TRUE(ring.peek(byte));
  EXPECT_EQ(byte, 10u);
  EXPECT_EQ(ring.size(), 2u);
  ASSERT_TRUE(ring.pop(byte));
  EXPECT_EQ(byte, 10u);
  ASSERT_TRUE(ring.peek(byte));
  EXPECT_EQ(byte, 20u);
}

TEST(SpscRing, KeepsOrderAndCountAcrossManyWraps) {
  SpscRing<4> ring;
  std::uint8_t expected = 0;
  std::uint8_t next = 0;
  std::uint32_t pushed = 0;
  std::uint32_t popped = 0;
  // 3 in (2 fit once 1 is queued), 2 out, repeated: the indices pass the capacity many times.
  for (int round = 0; round < 1000; ++round) {
    for (int i = 0; i < 3 && ring.push(next); ++i) {
      ++next;
      ++pushed;
    }
    ASSERT_EQ(ring.size(), pushed - popped);
    ASSERT_EQ(ring.free_space(), 3u - (pushed - popped));
    std::uint8_t byte = 0;
    for (int i = 0; i < 2 && ring.pop(byte); ++i) {
      ASSERT_EQ(byte, expected++);
      ++popped;
    }
  }
  EXPECT_GT(pushed, 1000u);
}

TEST(SpscRing, OneProducerThreadAndOneConsumerThreadLoseAndReorderNothing) {
  // The acquire/release pairing is what makes this hold; the threads stand for the interrupt
  // and the main loop.
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
  EXPECT_EQ(ring.size(), 0u);
}

}  // namespace

#include "odocal/drive/quadrature_decoder.hpp"

#include <gtest/gtest.h>

#include <cstdint>

#include "odocal/drive/velocity_estimator.hpp"

namespace odocal::drive {
namespace {

struct Levels {
  bool a;
  bool b;
};
// Forward (A leads B) order of the four states.
constexpr Levels kForward[4] = {{false, false}, {true, false}, {true, true}, {false, true}};

int index_of(bool a, bool b) {
  for (int i = 0; i < 4; ++i) {
    if (kForward[i].a == a && kForward[i].b == b)
      return i;
  }
  return -1;
}

TEST(QuadratureDecoder, EveryTransitionOfTheSixteen) {
  for (int from = 0; from < 4; ++from) {
    for (int to = 0; to < 4; ++to) {
      QuadratureDecoder decoder;
      decoder.reset(kForward[from].a, kForward[from].b);
      decoder.on_edge(kForward[to].a, kForward[to].b, 123u);
      const EncoderSnapshot s = decoder.snapshot();
      const int step = ((to - from) % 4 + 4) % 4;  // 1 forward, 3 backward, 2 illegal, 0 none
      SCOPED_TRACE(testing::Message() << "from " << from << " to " << to);
      switch (step) {
        case 0:
          EXPECT_EQ(s.count, 0u);
          EXPECT_EQ(s.edges, 0u);
          EXPECT_EQ(s.illegal, 0u);
          break;
        case 1:
          EXPECT_EQ(s.count, 1u);
          EXPECT_EQ(s.edges, 1u);
          EXPECT_EQ(s.last_edge_us, 123u);
          break;
        case 3:
          EXPECT_EQ(static_cast<std::int32_t>(s.count), -1);
          EXPECT_EQ(s.edges, 1u);
          break;
        case 2:
          EXPECT_EQ(s.count, 0u);
          EXPECT_EQ(s.illegal, 1u);
          EXPECT_EQ(s.edges, 0u);
          break;
      }
    }
  }
}

TEST(QuadratureDecoder, FullCyclesForwardThenReverseReturnToZero) {
  QuadratureDecoder decoder;
  decoder.reset(false, false);
  std::uint32_t t = 0;
  for (int i = 1; i <= 4 * 100; ++i) {
    const Levels& l = kForward[i % 4];
    decoder.on_edge(l.a, l.b, ++t);
  }
  EXPECT_EQ(decoder.snapshot().count, 400u);
  // Reverse direction in the middle of a cycle: the first step back counts -1 immediately.
  for (int i = 4 * 100 - 1; i >= -37; --i) {
    const Levels& l = kForward[((i % 4) + 4) % 4];
    decoder.on_edge(l.a, l.b, ++t);
  }
  EXPECT_EQ(static_cast<std::int32_t>(decoder.snapshot().count), -37);
  EXPECT_EQ(decoder.snapshot().illegal, 0u);
}

TEST(QuadratureDecoder, IllegalPairsCountAndKeepPosition) {
  QuadratureDecoder decoder;
  decoder.reset(false, false);
  decoder.on_edge(true, false, 1u);  // +1
  decoder.on_edge(false, true, 2u);  // 10 -> 01: both changed
  decoder.on_edge(true, false, 3u);  // 01 -> 10: both changed
  const EncoderSnapshot s = decoder.snapshot();
  EXPECT_EQ(s.count, 1u);
  EXPECT_EQ(s.illegal, 2u);
  EXPECT_EQ(s.last_edge_us, 1u);  // an illegal transition is not a timed edge
  // A glitch that reports the same state again changes nothing.
  decoder.on_edge(true, false, 4u);
  EXPECT_EQ(decoder.snapshot().count, 1u);
  EXPECT_EQ(decoder.snapshot().illegal, 2u);
}

TEST(QuadratureDecoder, RawCountWrapsAndTheWideReaderFollows) {
  // Going backwards from 0 wraps the raw 32-bit count to 0xFFFFFFFF...; the estimator's signed
  // modular difference turns it into negative wide positions without a jump.
  QuadratureDecoder decoder;
  decoder.reset(false, false);
  VelocityEstimator estimator(1440.0f);
  estimator.reset(decoder.snapshot(), 0u);
  int phase = 0;
  std::uint32_t t = 0;
  for (int i = 0; i < 10; ++i) {
    phase = (phase + 3) % 4;  // one step backwards
    decoder.on_edge(kForward[phase].a, kForward[phase].b, t += 100u);
  }
  EXPECT_EQ(decoder.snapshot().count, 0xFFFFFFF6u);
  estimator.update(decoder.snapshot(), t);
  EXPECT_EQ(estimator.position_counts(), -10);
  EXPECT_EQ(index_of(kForward[phase].a, kForward[phase].b), phase);
}

TEST(VelocityEstimator, WideSnapshotDifferenceAcrossTheWrap) {
  VelocityEstimator estimator(1440.0f);
  EncoderSnapshot s;
  s.count = 0xFFFFFFF0u;
  s.last_edge_us = 0xFFFFFF00u;
  estimator.reset(s, 0xFFFFFF00u);
  s.count = 0x00000010u;         // +32 counts across the wrap
  s.last_edge_us = 0x00000100u;  // 512 µs later, across the clock wrap too
  estimator.update(s, 0x00000180u);
  EXPECT_EQ(estimator.delta_counts(), 32);
  EXPECT_EQ(estimator.position_counts(), 32);
  const float expected = 32.0f * 6.28318530718f / 1440.0f / 512e-6f;
  EXPECT_NEAR(estimator.speed_radps(), expected, expected * 1e-5f);
}

// wiring_fix: a reversed decoder counts the same edges with the opposite sign and the same
// illegal count; a routed decoder advances another decoder's counters and keeps its own state.
TEST(QuadratureDecoder, ReversedCountsDownAndRoutedAdvancesTheOtherCounters) {
  QuadratureDecoder plain;
  QuadratureDecoder reversed;
  QuadratureDecoder sink;
  plain.reset(false, false);
  reversed.reset(false, false);
  reversed.route(sink, true);
  std::uint32_t t = 0u;
  for (int cycle = 0; cycle < 3; ++cycle) {
    for (int i = 1; i <= 4; ++i) {
      const Levels l = kForward[i % 4];
      plain.on_edge(l.a, l.b, ++t);
      reversed.on_edge(l.a, l.b, t);
    }
  }
  plain.on_edge(true, true, ++t);  // both channels at once: illegal
  reversed.on_edge(true, true, t);
  EXPECT_EQ(static_cast<std::int32_t>(plain.snapshot().count), 12);
  EXPECT_EQ(static_cast<std::int32_t>(sink.snapshot().count), -12);
  EXPECT_EQ(sink.snapshot().edges, 12u);
  EXPECT_EQ(sink.snapshot().illegal, 1u);
  EXPECT_EQ(sink.snapshot().last_edge_us, plain.snapshot().last_edge_us);
  EXPECT_EQ(reversed.snapshot().count, 0u);  // its own counters stay where they were
  // Routed back, it counts up again from its own (untouched) count.
  reversed.route(reversed, false);
  reversed.on_edge(false, true, ++t);  // 11 -> 01: forward
  EXPECT_EQ(static_cast<std::int32_t>(reversed.snapshot().count), 1);
}

}  // namespace
}  // namespace odocal::drive

// Encoder edges delivered by event: only a wheel whose shaft left its count computes edge
// instants. These tests hold what the decoder must see whatever the speed profile.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "odocal/drive/quadrature_decoder.hpp"
#include "odocal/random/xoshiro256.hpp"
#include "odocal/sim/encoder_wiring.hpp"
#include "odocal/sim/plant.hpp"

namespace odocal::sim {
namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

RobotModel no_slip_robot() {
  RobotModel m;
  m.slip_sigma = 0.0;
  m.measure_sigma_m = 0.0;
  m.measure_heading_sigma_rad = 0.0;
  return m;
}

void drive_wheel(Wheel& wheel, double duty) {
  wheel.forward().set(duty >= 0.0);
  wheel.pwm().set_duty(static_cast<float>(std::fabs(duty)));
}

/// Every edge either wheel delivers, in delivery order, forwarded to that wheel's decoder.
struct EdgeRecorder {
  struct Edge {
    int wheel;
    std::uint64_t t_ns;
  };
  struct Channel {
    EdgeRecorder* recorder;
    int wheel;
    drive::QuadratureDecoder decoder;
  };
  const Plant* plant = nullptr;
  std::vector<Edge> edges;
  Channel channels[2] = {{this, 0, {}}, {this, 1, {}}};

  static hal::EdgeSink sink(Channel& channel) {
    hal::EdgeSink s;
    s.edge = [](void* context, bool a, bool b, std::uint32_t t_us) {
      auto* c = static_cast<Channel*>(context);
      c->recorder->edges.push_back(Edge{c->wheel, c->recorder->plant->now_ns()});
      c->decoder.on_edge(a, b, t_us);
    };
    s.preset = [](void* context, bool a, bool b) {
      static_cast<Channel*>(context)->decoder.reset(a, b);
    };
    s.context = &channel;
    return s;
  }
};

/// The count the shaft angle is in: floor(angle·N/2π). `near` is set when the angle lies so close
/// to a count boundary (1e-9 count) that rounding may put it on either side.
std::int64_t count_of(double angle_rad, std::uint32_t counts_per_rev, bool& near) {
  const double counts = angle_rad * static_cast<double>(counts_per_rev) / two_pi;
  near = std::fabs(counts - std::round(counts)) < 1e-9;
  return static_cast<std::int64_t>(std::floor(counts));
}

/// Drives both wheels through random duty profiles (reversals, standstill below and at zero
/// duty, full speed) and checks after every advance, of random length from 1 ns to several
/// physics steps, that the edges delivered so far are exactly those the shaft angle crossed.
void check_random_profile(RobotModel model, std::uint64_t seed) {
  Plant plant(model, seed);
  EdgeRecorder recorder;
  recorder.plant = &plant;
  EncoderWiring left(plant.left().channel_a(), plant.left().channel_b(), plant.clock(),
                     EdgeRecorder::sink(recorder.channels[0]));
  EncoderWiring right(plant.right().channel_a(), plant.right().channel_b(), plant.clock(),
                      EdgeRecorder::sink(recorder.channels[1]));
  left.attach();
  right.attach();
  random::Xoshiro256 dice(seed);
  Wheel* const wheels[2] = {&plant.left(), &plant.right()};
  std::uint64_t t_ns = 0u;
  std::size_t checked = 0u;
  std::size_t standstill_checks = 0u;
  for (int segment = 0; segment < 60; ++segment) {
    for (Wheel* w : wheels) {
      const double pick = dice.uniform();
      // A quarter of the segments at zero duty (the wheel coasts to rest and stays), some below
      // the breakaway duty (~0.018), the rest anywhere in [-1, 1]: reversals through zero.
      const double duty = pick < 0.25 ? 0.0 : pick < 0.35 ? 0.01 : 2.0 * dice.uniform() - 1.0;
      drive_wheel(*w, duty);
    }
    const std::uint64_t segment_end = t_ns + 50'000'000u + dice.next_u64() % 400'000'000u;
    while (t_ns < segment_end) {
      const std::uint64_t kind = dice.next_u64() % 4u;
      const std::uint64_t span = kind == 0u   ? 1u + dice.next_u64() % 1000u  // inside a step
                                 : kind == 1u ? 1u + dice.next_u64() % 500'000u
                                              : 1u + dice.next_u64() % 3'000'000u;
      const std::size_t before = recorder.edges.size();
      const std::uint64_t from_ns = t_ns;
      t_ns += span;
      plant.advance_to_ns(t_ns);
      ASSERT_EQ(plant.now_ns(), t_ns);
      for (std::size_t i = before; i < recorder.edges.size(); ++i) {
        // Every edge inside the interval just simulated, never earlier than the one before it
        // (either wheel): the decoders see time run forwards.
        ASSERT_GE(recorder.edges[i].t_ns, from_ns);
        ASSERT_LE(recorder.edges[i].t_ns, t_ns);
        if (i > 0) {
          ASSERT_GE(recorder.edges[i].t_ns, recorder.edges[i - 1].t_ns) << "edge " << i;
        }
      }
      for (int k = 0; k < 2; ++k) {
        const Wheel& w = *wheels[k];
        bool near = false;
        const std::int64_t expected = count_of(w.angle_rad(), model.counts_per_rev, near);
        if (!near) {
          ASSERT_EQ(w.encoder_count(), expected)
              << "wheel " << k << " at " << t_ns << " ns, angle " << w.angle_rad();
        }
        const drive::EncoderSnapshot snap = recorder.channels[k].decoder.snapshot();
        ASSERT_EQ(static_cast<std::int32_t>(snap.count),
                  static_cast<std::int32_t>(w.encoder_count()));
        ASSERT_EQ(snap.illegal, 0u);
        if (w.speed_radps() == 0.0) {
          ++standstill_checks;
        }
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000u);
  EXPECT_GT(standstill_checks, 100u);  // the profile did reach standstill
  EXPECT_GT(recorder.edges.size(), 10000u);
}

TEST(EdgeDelivery, CountIsTheCountTheShaftIsInAfterEveryAdvanceOfRandomProfiles) {
  for (std::uint64_t seed = 1u; seed <= 3u; ++seed) {
    check_random_profile(no_slip_robot(), seed);
  }
}

TEST(EdgeDelivery, HoldsWithSlipCablesAndACoarseOddPhysicsStep) {
  RobotModel m;  // default noise, plus cables and a step that does not divide a millisecond
  m.bump_height_m = 0.005;
  m.physics_step_ns = 333'333u;
  m.counts_per_rev = 400u;
  check_random_profile(m, 9u);
}

TEST(EdgeDelivery, WheelAtRestDeliversNoEdge) {
  Plant plant(no_slip_robot(), 4u);
  EdgeRecorder recorder;
  recorder.plant = &plant;
  EncoderWiring left(plant.left().channel_a(), plant.left().channel_b(), plant.clock(),
                     EdgeRecorder::sink(recorder.channels[0]));
  left.attach();
  drive_wheel(plant.left(), 0.6);
  plant.advance_to_ns(500'000'000u);
  drive_wheel(plant.left(), 0.0);
  plant.advance_to_ns(2'000'000'000u);  // 15 time constants: friction has stopped it
  ASSERT_EQ(plant.left().speed_radps(), 0.0);
  const std::size_t edges = recorder.edges.size();
  const std::int64_t count = plant.left().encoder_count();
  plant.advance_to_ns(5'000'000'000u);
  EXPECT_EQ(recorder.edges.size(), edges);
  EXPECT_EQ(plant.left().encoder_count(), count);
}

/// Runs the left wheel forward with a fault injected on its channel A after 0.2 s; returns the
/// decoder's view and how many counts the shaft moved meanwhile.
struct FaultRun {
  drive::EncoderSnapshot before;
  drive::EncoderSnapshot after;
  std::int64_t counts_moved = 0;
};
FaultRun run_with_fault(ChannelFault fault) {
  Plant plant(no_slip_robot(), 6u);
  drive::QuadratureDecoder decoder;
  EncoderWiring wiring(plant.left().channel_a(), plant.left().channel_b(), plant.clock(),
                       drive::edge_sink(decoder));
  wiring.attach();
  drive_wheel(plant.left(), 0.5);
  plant.advance_to_ns(200'000'000u);
  FaultRun run;
  run.before = decoder.snapshot();
  const std::int64_t start = plant.left().encoder_count();
  wiring.set_fault(fault);
  plant.advance_to_ns(1'200'000'000u);
  run.after = decoder.snapshot();
  run.counts_moved = plant.left().encoder_count() - start;
  wiring.detach();
  return run;
}

TEST(EdgeDelivery, DeadChannelShowsOnlyBEdgesThatCountBackAndForth) {
  const FaultRun run = run_with_fault(ChannelFault::dead);
  ASSERT_GT(run.counts_moved, 1000);
  // Half the edges (those on B) reach the decoder; with A stuck they alternate up and down, so
  // the decoder's position stays within one count of where the fault began.
  const auto seen = static_cast<std::int64_t>(run.after.edges - run.before.edges);
  EXPECT_NEAR(static_cast<double>(seen), 0.5 * static_cast<double>(run.counts_moved), 1.0);
  const auto moved = static_cast<std::int32_t>(run.after.count - run.before.count);
  EXPECT_LE(std::abs(moved), 1);
  EXPECT_EQ(run.after.illegal, run.before.illegal);
}

TEST(EdgeDelivery, NoisyChannelGlitchesEveryFifthBEdge) {
  const FaultRun run = run_with_fault(ChannelFault::noisy);
  ASSERT_GT(run.counts_moved, 1000);
  // B edges are half the counts moved (±1); every 5th of them arrives with A flipped, which the
  // decoder sees as both lines changing: an illegal transition.
  const double b_edges = 0.5 * static_cast<double>(run.counts_moved);
  const auto illegal = static_cast<double>(run.after.illegal - run.before.illegal);
  EXPECT_NEAR(illegal, std::floor(b_edges / 5.0), 1.0);
}

}  // namespace
}  // namespace odocal::sim

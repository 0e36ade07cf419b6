// hal::WallSensor's lit-minus-ambient helper, on a hand-written fake that records each call.

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

#include "odocal/hal/wall_sensor.hpp"

namespace odocal::hal {
namespace {

enum class Call : std::uint8_t { emitter_off, emitter_on, read, settle };

// Returns `dark` with the emitter off and `bright` with it on; records the calls in order.
class RecordingSensor final : public WallSensor {
 public:
  RecordingSensor(std::uint16_t dark, std::uint16_t bright) : dark_(dark), bright_(bright) {}
  std::array<Call, 16> calls{};
  std::uint32_t count = 0u;
  bool on = true;  // starts on: the helper must switch it off before the ambient reading

 private:
  void record(Call call) {
    if (count < calls.size()) {
      calls[count++] = call;
    }
  }
  void do_set_emitter(bool emitter_on) override {
    on = emitter_on;
    record(emitter_on ? Call::emitter_on : Call::emitter_off);
  }
  std::uint16_t do_read_counts() override {
    record(Call::read);
    return on ? bright_ : dark_;
  }
  std::uint32_t do_settle_us() const override { return 30u; }
  void do_wait_settle() override { record(Call::settle); }
  std::uint16_t dark_;
  std::uint16_t bright_;
};

TEST(WallSensorHelper, ReadsAmbientThenLitAfterTheSettleAndLeavesTheEmitterOff) {
  RecordingSensor sensor(300u, 1300u);
  EXPECT_EQ(sensor.read_lit_counts(), 1000u);
  const std::array<Call, 6> expected{Call::emitter_off, Call::read, Call::emitter_on,
                                     Call::settle,      Call::read, Call::emitter_off};
  ASSERT_EQ(sensor.count, expected.size());
  for (std::uint32_t i = 0u; i < expected.size(); ++i) {
    EXPECT_EQ(sensor.calls[i], expected[i]) << i;
  }
  EXPECT_FALSE(sensor.on);
  EXPECT_EQ(sensor.settle_us(), 30u);
}

TEST(WallSensorHelper, ALitReadingBelowTheAmbientGivesZero) {
  RecordingSensor sensor(300u, 290u);
  EXPECT_EQ(sensor.read_lit_counts(), 0u);
}

TEST(WallSensorHelper, ClampsABackendReadingAboveTwelveBits) {
  RecordingSensor sensor(5000u, 65535u);
  EXPECT_EQ(sensor.read_counts(), WallSensor::full_scale_counts);
  EXPECT_EQ(sensor.read_lit_counts(), 0u);  // both clamped to full scale
}

}  // namespace
}  // namespace odocal::hal

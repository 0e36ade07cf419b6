#include "odocal/drive/velocity_estimator.hpp"

#include <cmath>
#include <numbers>

namespace odocal::drive {
namespace {
constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
}

VelocityEstimator::VelocityEstimator(float counts_per_rev, std::uint32_t stop_timeout_us)
    : rad_per_count_(kTwoPi / counts_per_rev), stop_timeout_us_(stop_timeout_us) {}

void VelocityEstimator::set_counts_per_rev(float counts_per_rev) {
  if (counts_per_rev > 0.0f && std::isfinite(counts_per_rev)) {
    rad_per_count_ = kTwoPi / counts_per_rev;
  }
}

void VelocityEstimator::reset(const EncoderSnapshot& snapshot, std::uint32_t now_us) {
  initialised_ = true;
  last_count_ = snapshot.count;
  window_edge_us_ = snapshot.last_edge_us;
  pending_counts_ = 0;
  delta_ = 0;
  speed_radps_ = 0.0f;
  since_edge_us_ = now_us - snapshot.last_edge_us;
}

void VelocityEstimator::update(const EncoderSnapshot& snapshot, std::uint32_t now_us) {
  if (!initialised_) {
    reset(snapshot, now_us);
    return;
  }
  // Signed modular difference: correct across the 2^32 wrap of the raw count.
  delta_ = static_cast<std::int32_t>(snapshot.count - last_count_);
  last_count_ = snapshot.count;
  position_ += delta_;
  since_edge_us_ = now_us - snapshot.last_edge_us;

  if (delta_ != 0) {
    pending_counts_ += delta_;
    const std::uint32_t span_us = snapshot.last_edge_us - window_edge_us_;
    if (span_us != 0u) {
      // M/T: whole counts over the time between the last edges of two windows.
      speed_radps_ = static_cast<float>(pending_counts_) * rad_per_count_ /
                     (static_cast<float>(span_us) * 1e-6f);
      pending_counts_ = 0;
      window_edge_us_ = snapshot.last_edge_us;
    }
    return;
  }

  // No net motion this window: the wheel turned less than one count since the last edge, so
  // |speed| is at most one count over the time since then.
  const std::uint32_t quiet_us = now_us - window_edge_us_;
  if (quiet_us >= stop_timeout_us_) {
    speed_radps_ = 0.0f;
    pending_counts_ = 0;
    return;
  }
  if (quiet_us != 0u) {
    const float bound = rad_per_count_ / (static_cast<float>(quiet_us) * 1e-6f);
    if (speed_radps_ > bound) {
      speed_radps_ = bound;
    } else if (speed_radps_ < -bound) {
      speed_radps_ = -bound;
    }
  }
}

}  // namespace odocal::drive

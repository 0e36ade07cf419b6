#include "odocal/drive/trial.hpp"

#include "odocal/math/numeric.hpp"

namespace odocal::drive {

void TrialRecorder::begin(PathId path, float length_m, std::int64_t counts_l,
                          std::int64_t counts_r) {
  phase_ = Phase::moving;
  path_ = path;
  length_m_ = length_m;
  start_l_ = counts_l;
  start_r_ = counts_r;
  seen_l_ = counts_l;
  seen_r_ = counts_r;
  elapsed_us_ = 0u;
  settle_us_ = 0u;
  still_us_ = 0u;
}

bool TrialRecorder::update(bool moving, std::int64_t counts_l, std::int64_t counts_r,
                           const Pose& pose, std::uint32_t dt_us, float still_ms) {
  if (!advance(moving, counts_l, counts_r, dt_us, still_ms)) {
    return false;
  }
  last_.end = pose;
  return true;
}

bool TrialRecorder::update(bool moving, std::int64_t counts_l, std::int64_t counts_r,
                           const Odometry& odometry, std::uint32_t dt_us, float still_ms) {
  if (!advance(moving, counts_l, counts_r, dt_us, still_ms)) {
    return false;
  }
  last_.end = odometry.pose();
  return true;
}

bool TrialRecorder::advance(bool moving, std::int64_t counts_l, std::int64_t counts_r,
                            std::uint32_t dt_us, float still_ms) {
  if (phase_ == Phase::none) {
    return false;
  }
  elapsed_us_ += dt_us;
  if (counts_l != seen_l_ || counts_r != seen_r_) {
    still_us_ = 0u;
    seen_l_ = counts_l;
    seen_r_ = counts_r;
  } else {
    still_us_ += dt_us;
  }
  if (phase_ == Phase::moving) {
    if (moving) {
      return false;
    }
    phase_ = Phase::settling;
    settle_us_ = 0u;
  } else {
    settle_us_ += dt_us;
  }
  const bool at_rest = static_cast<float>(still_us_) * 1e-3f >= still_ms;
  if (!at_rest && settle_us_ < max_settle_ms * 1000u) {
    return false;
  }
  // The record is written in place: the tick owns it, readers take it under a critical section.
  last_.number = next_number_++;
  last_.path = path_;
  last_.length_m = length_m_;
  last_.duration_ms = static_cast<std::uint32_t>(math::divide_u64(elapsed_us_ + 500u, 1000u));
  last_.count_l = counts_l - start_l_;
  last_.count_r = counts_r - start_r_;
  phase_ = Phase::none;
  return true;
}

void TrialLog::push(const TrialRecord& record) {
  if (count_ < capacity) {
    records_[(first_ + count_) % capacity] = record;
    ++count_;
  } else {
    records_[first_] = record;
    first_ = (first_ + 1u) % capacity;
  }
}

const TrialRecord& TrialLog::at(std::size_t i) const {
  return records_[(first_ + (i < count_ ? i : 0u)) % capacity];
}

const TrialRecord* TrialLog::find(std::uint32_t number) const {
  for (std::size_t i = 0; i < count_; ++i) {
    if (at(i).number == number) {
      return &at(i);
    }
  }
  return nullptr;
}

const TrialRecord* TrialLog::latest() const {
  return count_ == 0u ? nullptr : &at(count_ - 1u);
}

}  // namespace odocal::drive

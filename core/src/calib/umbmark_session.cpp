#include "odocal/calib/umbmark_session.hpp"

namespace odocal::calib {

void UmbmarkSession::clear() {
  cw_count_ = 0u;
  ccw_count_ = 0u;
  solved_ = false;
}

bool UmbmarkSession::add(bool clockwise, const Error& error) {
  std::size_t& count = clockwise ? cw_count_ : ccw_count_;
  if (count >= capacity) {
    return false;
  }
  (clockwise ? cw_ : ccw_)[count] = error;
  ++count;
  solved_ = false;
  return true;
}

void UmbmarkSession::set_side_mm(float side_mm) {
  side_mm_ = side_mm;
  solved_ = false;
}

UmbmarkStatus UmbmarkSession::solve(float wheelbase_mm, bool exact) {
  UmbmarkInputOf<float> input;
  input.cw = cw_.data();
  input.cw_count = cw_count_;
  input.ccw = ccw_.data();
  input.ccw_count = ccw_count_;
  input.side_mm = side_mm_;
  input.wheelbase_mm = wheelbase_mm;
  input.exact = exact;
  Result result;
  const UmbmarkStatus status = solve_umbmark(input, result);
  if (status == UmbmarkStatus::ok) {
    result_ = result;
    solved_ = true;
  }
  return status;
}

}  // namespace odocal::calib

#include "odocal/drive/quadrature_decoder.hpp"

#include <cstdint>

namespace odocal::drive {
namespace {

// Marks a transition where both channels changed: direction unknown, an edge was missed.
constexpr std::int8_t kIllegal = 2;

// Index: (previous state << 2) | new state, a state being (A << 1) | B.
// Forward (A leads B) walks 0 -> 2 -> 3 -> 1 -> 0; backward walks the other way.
constexpr std::int8_t kTransition[16] = {
    // to:  00         01         10         11
    0,        -1,       +1,       kIllegal,  // from 00
    +1,       0,        kIllegal, -1,        // from 01
    -1,       kIllegal, 0,        +1,        // from 10
    kIllegal, +1,       -1,       0,         // from 11
};

constexpr std::uint8_t state_of(bool a, bool b) {
  return static_cast<std::uint8_t>((a ? 2u : 0u) | (b ? 1u : 0u));
}

}  // namespace

void QuadratureDecoder::reset(bool a, bool b) {
  state_ = state_of(a, b);
}

void QuadratureDecoder::on_edge(bool a, bool b, std::uint32_t now_us) {
  const std::uint8_t next = state_of(a, b);
  const std::int8_t step = kTransition[(state_ << 2) | next];
  state_ = next;
  if (step == kIllegal) {
    ++illegal_;
  } else if (step != 0) {
    // Modular arithmetic: the raw count wraps at 2^32 and readers take differences.
    count_ += static_cast<std::uint32_t>(static_cast<std::int32_t>(step));
    ++edges_;
    last_edge_us_ = now_us;
  }
}

}  // namespace odocal::drive

#include "odocal/drive/quadrature_decoder.hpp"

#include <cstdint>

namespace odocal::drive {

void QuadratureDecoder::reset(bool a, bool b) {
  state_ = quadrature::state_of(a, b);
}

}  // namespace odocal::drive

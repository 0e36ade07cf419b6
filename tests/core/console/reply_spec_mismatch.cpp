// Must not compile: a spec whose directive does not match its value (ctest
// reply_spec_mismatch_does_not_compile expects the compiler to name the failed check).

#include <cstdint>

#include "odocal/console/reply_spec.hpp"

namespace {

template <typename... Values>
const char* spec_text(odocal::console::ReplySpec<std::type_identity_t<Values>...> spec, Values...) {
  return spec.text();
}

}  // namespace

const char* mismatched() {
  const std::int32_t count = -1;
  return spec_text("count=%u", count);  // %u with a signed value
}

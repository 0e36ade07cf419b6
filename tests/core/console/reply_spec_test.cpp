// A reply spec's directives against its values' types (reply_spec.hpp). The compile-time side,
// that a mismatched spec does not build, is the ctest `reply_spec_mismatch_does_not_compile`.

#include "odocal/console/reply_spec.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace odocal::console {
namespace {

using U64 = const std::uint64_t*;
using I64 = const std::int64_t*;

TEST(ReplySpec, EachDirectiveTakesItsOwnType) {
  EXPECT_TRUE((spec_matches<std::uint32_t>("n=%u", true)));
  EXPECT_TRUE((spec_matches<std::uint8_t>("n=%u", true)));
  EXPECT_TRUE((spec_matches<std::size_t>("n=%u", true)));
  EXPECT_TRUE((spec_matches<std::int32_t>("n=%i", true)));
  EXPECT_TRUE((spec_matches<std::int16_t>("n=%i", true)));
  EXPECT_TRUE((spec_matches<U64, I64>("t=%U c=%I", true)));
  EXPECT_TRUE((spec_matches<const char*>("path=%s", true)));
  for (const char* spec : {"x=%0", "x=%3", "x=%9"}) {
    EXPECT_TRUE((spec_matches<float>(spec, true))) << spec;
  }
  EXPECT_TRUE((spec_matches<>("ok", true)));
}

TEST(ReplySpec, AMismatchedTypeIsRefused) {
  EXPECT_FALSE((spec_matches<std::int32_t>("n=%u", true)));  // a negative count printed as 2^32-1
  EXPECT_FALSE((spec_matches<std::uint32_t>("n=%i", true)));
  EXPECT_FALSE((spec_matches<float>("n=%u", true)));
  EXPECT_FALSE((spec_matches<std::uint32_t>("x=%3", true)));
  EXPECT_FALSE((spec_matches<double>("x=%3", true)));        // the robot has no double
  EXPECT_FALSE((spec_matches<std::int64_t>("n=%i", true)));  // 64-bit values go by address
  EXPECT_FALSE((spec_matches<I64>("n=%U", true)));
  EXPECT_FALSE((spec_matches<bool>("n=%u", true)));
  EXPECT_FALSE((spec_matches<const char*>("n=%u", true)));
}

TEST(ReplySpec, DirectivesAndValuesMustBeAsMany) {
  EXPECT_FALSE((spec_matches<std::uint32_t>("ok", true)));
  EXPECT_FALSE((spec_matches<>("n=%u", true)));
  EXPECT_FALSE((spec_matches<std::uint32_t>("a=%u b=%u", true)));
  EXPECT_FALSE((spec_matches<std::uint32_t, float>("a=%u", true)));
}

TEST(ReplySpec, UnknownDirectivesAndATrailingPercentAreRefused) {
  EXPECT_FALSE((spec_matches<std::uint32_t>("n=%d", true)));
  EXPECT_FALSE((spec_matches<std::uint32_t>("n=%%", true)));
  EXPECT_FALSE((spec_matches<std::uint32_t>("n=%u%", true)));
  EXPECT_FALSE((spec_matches<>("100%", true)));
}

TEST(ReplySpec, AShorterSpecLeavesOutAtLeastTheLastValue) {
  // `run unseen`'s reply has no length: the shorter spec of a two-spec reply.
  EXPECT_TRUE((spec_matches<const char*, std::uint32_t, float>("path=%s segments=%u", false)));
  EXPECT_TRUE((spec_matches<const char*, std::uint32_t>("ok", false)));
  EXPECT_FALSE((spec_matches<const char*, std::uint32_t>("path=%s segments=%u", false)));
  EXPECT_FALSE((spec_matches<const char*, std::uint32_t>("segments=%u", false)));  // out of order
}

TEST(ReplySpec, ASpecBuiltAtCompileTimeKeepsItsText) {
  static constexpr char text[] = "ok hz=%3";
  constexpr ReplySpec<float> spec(text);
  static_assert(spec.text() == text);
  constexpr LeadingReplySpec<const char*, float> shorter("ok path=%s");
  EXPECT_STREQ(shorter.text(), "ok path=%s");
}

}  // namespace
}  // namespace odocal::console

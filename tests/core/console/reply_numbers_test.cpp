// Numbers appended to a reply line, at every free space: a number is whole or absent, the text
// before it (key, sign) is cut off byte by byte, as the reply has always done. And the names of
// the error codes.

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

#include "odocal/console/reply.hpp"
#include "text_reference.hpp"

namespace odocal::console {
namespace {

class TestReply : public Reply {
 public:
  TestReply(char* buffer, std::size_t capacity) : Reply(buffer, capacity) {}
  [[nodiscard]] std::string str() const { return std::string(data(), size()); }
};

/// What the reply holds after appending `text` cut to fit, then `number` whole or not at all.
std::string expected_line(const std::string& text, const std::string& number,
                          std::size_t capacity) {
  std::string line = text.substr(0u, capacity);
  if (line.size() + number.size() <= capacity) {
    line += number;
  }
  return line;
}

std::string reference_unsigned(std::uint64_t value) {
  char digits[32];
  return std::string(digits, reference::format_unsigned(value, digits, sizeof digits));
}

TEST(ReplyNumbers, SignedPairsAtEveryFreeSpace) {
  const std::int64_t values[] = {0,
                                 1,
                                 -1,
                                 9,
                                 -10,
                                 -9054,
                                 2147483647,
                                 -2147483648LL,
                                 -4294967296LL,
                                 std::numeric_limits<std::int64_t>::max(),
                                 std::numeric_limits<std::int64_t>::min()};
  for (std::int64_t value : values) {
    const std::uint64_t magnitude =
        value < 0 ? 0u - static_cast<std::uint64_t>(value) : static_cast<std::uint64_t>(value);
    const std::string text = value < 0 ? " count_l=-" : " count_l=";
    for (std::size_t capacity = 0u; capacity <= 40u; ++capacity) {
      char buffer[64];
      TestReply reply(buffer, capacity);
      reply.pair_i("count_l", value);
      EXPECT_EQ(reply.str(), expected_line(text, reference_unsigned(magnitude), capacity))
          << value << " in " << capacity;
    }
  }
}

TEST(ReplyNumbers, UnsignedAndFixedPairsAtEveryFreeSpace) {
  const std::uint64_t values[] = {0u, 7u, 1000u, 4294967295u, 18446744073709551615ull};
  for (std::uint64_t value : values) {
    for (std::size_t capacity = 0u; capacity <= 40u; ++capacity) {
      char buffer[64];
      TestReply reply(buffer, capacity);
      reply.pair_u("t_ms", value);
      EXPECT_EQ(reply.str(), expected_line(" t_ms=", reference_unsigned(value), capacity));
    }
  }
  const float floats[] = {0.0f, -0.0004f, 151.58f, -2.5f, 1.5e15f, -1e30f};
  for (float value : floats) {
    for (int decimals = 0; decimals <= 9; ++decimals) {
      char digits[64];
      const std::string number(digits,
                               reference::format_fixed(value, decimals, digits, sizeof digits));
      for (std::size_t capacity = 0u; capacity <= 40u; ++capacity) {
        char buffer[64];
        TestReply reply(buffer, capacity);
        reply.pair("x_mm", value, decimals);
        EXPECT_EQ(reply.str(), expected_line(" x_mm=", number, capacity));
      }
    }
  }
}

TEST(ReplyNumbers, ErrorCodeNamesByCode) {
  // Each code's name, as the switch that named them before wrote them.
  const char* names[] = {"line_too_long", "non_ascii",     "unknown_command", "unknown_parameter",
                         "wrong_arity",   "bad_argument",  "bad_number",      "out_of_range",
                         "busy",          "fault",         "rejected",        "store_error",
                         "store_empty",   "store_version", "umbmark_full",    "umbmark_failed",
                         "not_solved",    "no_trial",      "lateral_full",    "lateral_failed",
                         "store_corrupt", "no_sensors"};
  for (int code = 0; code < 22; ++code) {
    EXPECT_STREQ(error_code_name(static_cast<ErrorCode>(code)), names[code]) << code;
  }
  EXPECT_EQ(ErrorCode::store_corrupt, static_cast<ErrorCode>(20));
  EXPECT_EQ(ErrorCode::no_sensors, static_cast<ErrorCode>(21));
  EXPECT_STREQ(error_code_name(static_cast<ErrorCode>(22)), "unknown");
  EXPECT_STREQ(error_code_name(static_cast<ErrorCode>(255)), "unknown");
}

}  // namespace
}  // namespace odocal::console

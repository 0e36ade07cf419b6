#pragma once
/// @file
/// A reply line's spec (`"ok v_mps=%3 ms=%u"`), checked against the types of its values when the
/// code is compiled. The console writes its replies from specs (Console::append, send_line): one
/// shared writer instead of a call per key and value, which the robot's flash needs. The values
/// travel to that writer in an untagged union; this check is what keeps a directive and its value
/// from disagreeing, so a mismatch is a compile error, not a wrong reply.
///
/// Directives: `%u` an unsigned whole number of at most 32 bits (size_t on the host), `%i` a
/// signed one of at most 32 bits, `%U` / `%I` the address of a 64-bit unsigned / signed one,
/// `%s` a NUL-ended text, `%0`..`%9` a float with that many decimals. Nothing else follows a `%`.

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace odocal::console {

namespace spec_detail {

/// The directive letter a value of type T is written with; 0 when none.
template <typename T>
constexpr char directive_of() {
  using V = std::remove_cv_t<T>;
  if constexpr (std::is_same_v<V, bool>) {
    return 0;  // a bool is written as 0u / 1u, chosen at the call site
  } else if constexpr (std::is_integral_v<V> && std::is_unsigned_v<V>) {
    return sizeof(V) <= sizeof(std::size_t) ? 'u' : 0;
  } else if constexpr (std::is_integral_v<V> && std::is_signed_v<V>) {
    return sizeof(V) <= sizeof(std::int32_t) ? 'i' : 0;
  } else if constexpr (std::is_same_v<V, float>) {
    return 'f';  // %0..%9
  } else if constexpr (std::is_same_v<V, const char*> || std::is_same_v<V, char*>) {
    return 's';
  } else if constexpr (std::is_same_v<V, const std::uint64_t*> ||
                       std::is_same_v<V, std::uint64_t*>) {
    return 'U';
  } else if constexpr (std::is_same_v<V, const std::int64_t*> || std::is_same_v<V, std::int64_t*>) {
    return 'I';
  } else {
    return 0;
  }
}

}  // namespace spec_detail

/// True when `spec`'s directives take `Values` in order: all of them (`all`), or the first few
/// (a spec chosen at run time that leaves trailing values out, see Console::send_line's
/// two-spec form).
template <typename... Values>
constexpr bool spec_matches(const char* spec, bool all) {
  constexpr char wanted[] = {spec_detail::directive_of<Values>()..., '\0'};
  std::size_t used = 0u;
  for (const char* p = spec; *p != '\0'; ++p) {
    if (*p != '%') {
      continue;
    }
    ++p;
    const char code = *p;
    if (code == '\0' || used == sizeof...(Values)) {
      return false;  // a % at the end, or more directives than values
    }
    const char kind = code >= '0' && code <= '9' ? 'f' : code;
    if (kind != wanted[used]) {
      return false;  // an unknown directive, or one that does not match its value's type
    }
    ++used;
  }
  return all ? used == sizeof...(Values) : used < sizeof...(Values);
}

/// Called only when a spec does not match: not constexpr, so a consteval check that reaches it
/// does not compile, and the compiler's message names this function.
void reply_spec_does_not_match_its_values();

/// A spec checked against `Values` when compiled: with `all_values`, its directives take every
/// one of them, in order; without, only the first few (at least one left out: the shorter
/// alternative of a two-spec reply whose last values are not always written). Built from a string
/// literal (consteval): `send_line("ok hz=%3", hz)` checks "%3" against `float`.
template <bool all_values, typename... Values>
class BasicReplySpec {
 public:
  // NOLINTNEXTLINE(google-explicit-constructor): a literal converts, as std::format_string does
  consteval BasicReplySpec(const char* text) : text_(text) {
    if (!spec_matches<Values...>(text, all_values)) {
      reply_spec_does_not_match_its_values();
    }
  }
  [[nodiscard]] constexpr const char* text() const { return text_; }

 private:
  const char* text_;
};

/// A spec that writes every one of `Values`.
template <typename... Values>
using ReplySpec = BasicReplySpec<true, Values...>;

/// A spec that writes only the first of `Values`.
template <typename... Values>
using LeadingReplySpec = BasicReplySpec<false, Values...>;

}  // namespace odocal::console

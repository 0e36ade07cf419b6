// The run's tick log as it comes over the line: each `# ticks` line read (checked with its CRC
// when the robot streams them so), and, for unchecked lines on a line seen to damage bytes, the
// samples a damaged digit left readable but wrong found and dropped.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "odocal/console/text.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

namespace {

/// How far sample i of `ticks` leaves the line its neighbours draw (counts, the worse wheel), in
/// units of what braking can bend it by (3 counts and a quarter of the neighbours' step): above 1
/// it is a jump no wheel makes.
double bend(const std::vector<TickSample>& ticks, std::size_t i) {
  const TickSample& a = ticks[i - 1];
  const TickSample& b = ticks[i + 1];
  const double share = (ticks[i].t_ms - a.t_ms) / (b.t_ms - a.t_ms);
  double worst = 0.0;
  for (int side = 0; side < 2; ++side) {
    const double before = static_cast<double>(side == 0 ? a.count_l : a.count_r);
    const double after = static_cast<double>(side == 0 ? b.count_l : b.count_r);
    const double here = static_cast<double>(side == 0 ? ticks[i].count_l : ticks[i].count_r);
    worst = std::max(worst, std::fabs(here - (before + share * (after - before))) /
                                (3.0 + 0.25 * std::fabs(after - before)));
  }
  return worst;
}

}  // namespace

std::optional<TickSample> read_tick_line(const std::string& line, bool checked) {
  std::string text = line;
  if (checked) {
    // " crc=N" ends the line; N is the CRC of every byte before it.
    const std::size_t at = line.rfind(" crc=");
    const auto crc =
        at == std::string::npos ? std::nullopt : toolkit::parse_integer(line.substr(at + 5));
    if (!crc || *crc < 0 || *crc > 0xFFFF ||
        static_cast<std::uint16_t>(*crc) != console::crc16(line.data(), at)) {
      return std::nullopt;
    }
    text = line.substr(0, at);
  }
  const auto pairs = hash_line_pairs(text);
  const auto t = pairs.find("t_ms"), l = pairs.find("count_l"), c = pairs.find("count_r");
  const auto tv = t == pairs.end() ? std::nullopt : toolkit::parse_real(t->second);
  const auto lv = l == pairs.end() ? std::nullopt : toolkit::parse_integer(l->second);
  const auto cv = c == pairs.end() ? std::nullopt : toolkit::parse_integer(c->second);
  if (text.rfind("# ticks ", 0) != 0 || pairs.size() != 3u || !tv || !lv || !cv) {
    return std::nullopt;
  }
  return TickSample{*tv, *lv, *cv};
}

/// Removes the samples a line that damages bytes left readable but wrong: first those whose time
/// is out of order (of two in the wrong order, the one its further neighbours disown), then,
/// worst first, those whose counts jump off the path their neighbours draw (the wheels cannot
/// jump and come back). The first row (two samples at rest that agreed) and the last (the end
/// row from `trial`, read twice) stay. Returns how many.
std::size_t drop_damaged(std::vector<TickSample>& ticks) {
  std::size_t removed = 0;
  for (std::size_t i = 0; i + 1 < ticks.size();) {
    if (ticks[i].t_ms < ticks[i + 1].t_ms) {
      ++i;
      continue;
    }
    // i or i + 1 is wrong: i if it is also after i + 2, else i + 1 (never the first row).
    const bool first_wrong =
        i > 0u && (i + 2 >= ticks.size() || ticks[i].t_ms >= ticks[i + 2].t_ms);
    ticks.erase(ticks.begin() + static_cast<std::ptrdiff_t>(first_wrong ? i : i + 1));
    ++removed;
    i = i > 0u ? i - 1 : 0u;
  }
  for (;;) {
    std::size_t worst_at = 0;
    double worst = 1.0;
    for (std::size_t i = 1; i + 1 < ticks.size(); ++i) {
      const double b = bend(ticks, i);
      if (b > worst) {
        worst = b;
        worst_at = i;
      }
    }
    if (worst_at == 0u) {
      return removed;
    }
    ticks.erase(ticks.begin() + static_cast<std::ptrdiff_t>(worst_at));
    ++removed;
  }
}

}  // namespace odocal::host::session

// Internal to the session: the runs the final fit explains worse than the others (auto_plan.hpp,
// SuspectRun), a last check after every run was judged by the others (run_jury.hpp).

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "auto_plan.hpp"
#include "odocal/host/fit_noise.hpp"

namespace odocal::host::session::auto_plan {

std::vector<SuspectRun> suspect_runs(const std::vector<TickLog>& logs, const FitNominal& nominal,
                                     const FitGeometry& geometry) {
  std::vector<SuspectRun> all;
  for (std::size_t i = 0; i < logs.size(); ++i) {
    const TickLog& log = logs[i];
    if (log.rows.size() < 2 || !log.rows.back().has_xy) {
      continue;
    }
    const EndSensitivity e = end_sensitivity(log, 0, log.rows.size() - 1, nominal, geometry);
    const TickRow& end = log.rows.back();
    SuspectRun r;
    r.index = i;
    r.position_mm = std::hypot(end.x_mm - e.end[0], end.y_mm - e.end[1]);
    const double heading_rad =
        end.has_theta ? std::remainder(end.theta_deg * kPi / 180.0 - e.end[2], 2.0 * kPi) : 0.0;
    r.heading_deg = heading_rad * 180.0 / kPi;
    r.residual_mm = std::hypot(r.position_mm, heading_rad * kHeadingLengthMm);
    all.push_back(r);
  }
  std::vector<SuspectRun> out;
  if (all.size() < 5) {
    return out;  // too few runs to say what is typical
  }
  std::vector<double> sizes;
  for (const SuspectRun& r : all) {
    sizes.push_back(r.residual_mm);
  }
  std::nth_element(sizes.begin(), sizes.begin() + static_cast<std::ptrdiff_t>(sizes.size() / 2),
                   sizes.end());
  const double median = sizes[sizes.size() / 2];
  for (SuspectRun r : all) {
    if (r.residual_mm > kSuspectFactor * median && r.residual_mm > kSuspectFloorMm) {
      r.typical_mm = median;
      out.push_back(r);
    }
  }
  return out;
}

nlohmann::json describe_suspects(const std::vector<SuspectRun>& suspects, const Context& c,
                                 std::size_t first_run, std::string& named) {
  nlohmann::json listed = nlohmann::json::array();
  named.clear();
  for (const SuspectRun& s : suspects) {
    const std::size_t number = first_run + s.index;
    const std::string& label = c.runs.at(number - 1).label;
    listed.push_back({{"run", number},
                      {"label", label},
                      {"position_mm", s.position_mm},
                      {"heading_deg", s.heading_deg},
                      {"typical_mm", s.typical_mm}});
    named += fmt::format(
        "{}run {} ({}: {:.0f} mm and {:.1f} deg off the fit, the runs typically {:.1f} mm)",
        named.empty() ? "" : "; ", number, label, s.position_mm, s.heading_deg, s.typical_mm);
  }
  return listed;
}

}  // namespace odocal::host::session::auto_plan

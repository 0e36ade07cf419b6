#include "reading_check.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "odocal/toolkit/numbers.hpp"

namespace odocal::host::session {

namespace {

/// `value` with `decimals` decimals, trailing zeros dropped down to one.
std::string number_text(double value, int decimals) {
  std::string text = fmt::format("{:.{}f}", value, decimals);
  while (decimals > 1 && text.back() == '0') {
    text.pop_back();
    --decimals;
  }
  return text == "-0.0" ? "0.0" : text;
}

}  // namespace

std::string pose_text(const SessionPose& p, int decimals) {
  std::string text = number_text(p.x_mm, decimals) + " " + number_text(p.y_mm, decimals);
  if (p.theta_deg) {
    text += " " + number_text(*p.theta_deg, decimals);
  }
  return text;
}

int decimals_of(const SessionPose& p) {
  int most = 1;
  for (const double v : {p.x_mm, p.y_mm, p.theta_deg.value_or(0.0)}) {
    int d = 1;
    while (d < 3 && std::fabs(v * std::pow(10.0, d) - std::round(v * std::pow(10.0, d))) > 1e-6) {
      ++d;
    }
    most = std::max(most, d);
  }
  return most;
}

int typed_decimals(const std::string& typed) {
  int most = 1;
  int run = -1;  // digits after a decimal point so far, -1 outside one
  for (const char c : typed) {
    if (c == '.') {
      run = 0;
    } else if (run >= 0 && std::isdigit(static_cast<unsigned char>(c)) != 0) {
      most = std::max(most, ++run);
    } else {
      run = -1;
    }
  }
  return std::min(most, 4);
}

namespace {

/// A typed heading past this is asked about (half a turn, and the odometry's wrap and noise).
constexpr double max_typed_heading_deg = 200.0;

/// Where the robot ends when its wheels are `k_l`, `k_r` times the size the odometry believes and
/// its wheelbases `k_b` times, the odometry having driven `path` exactly (the one model's
/// advance_believing, segment by segment).
drive::model::PoseOf<double> end_with(const drive::Path& path,
                                      const drive::model::Geometry<double>& g, double k_l,
                                      double k_r, double k_b) {
  const drive::model::Geometry<double> truth{k_l * g.left_diameter, k_r * g.right_diameter,
                                             k_b * g.wheelbase, k_b * g.wheelbase_arc};
  drive::model::PoseOf<double> pose;
  for (std::uint8_t i = 0; i < path.count; ++i) {
    drive::model::advance_believing(pose, g, truth,
                                    1e3 * static_cast<double>(path.segments[i].distance_m),
                                    static_cast<double>(path.segments[i].angle_rad));
  }
  return pose;
}

/// The residual of a reading (reading − odometry): position mm, heading deg wrapped to ±180.
struct Residual {
  double x_mm = 0.0;
  double y_mm = 0.0;
  std::optional<double> theta_deg;
};

Residual residual(const SessionPose& reading, const SessionPose& odom) {
  Residual r{reading.x_mm - odom.x_mm, reading.y_mm - odom.y_mm, std::nullopt};
  if (reading.theta_deg && odom.theta_deg) {
    r.theta_deg = std::remainder(*reading.theta_deg - *odom.theta_deg, 360.0);
  }
  return r;
}

/// The run-to-run scatter a reading is allowed, heading: a floor and a share of the turning.
double noise_heading_deg(const PathExtent& e) {
  return reading_noise::heading_deg + reading_noise::heading_per_deg * e.turned_deg +
         (e.wheelbase_mm > 0.0
              ? reading_noise::heading_per_wheelbase_deg * e.length_mm / e.wheelbase_mm
              : 0.0);
}

/// Position: a floor, a share of the distance, and the heading's scatter carried over half the
/// path (a heading error made on the way moves the stop by the distance driven after it).
double noise_position_mm(const PathExtent& e) {
  return reading_noise::position_mm + reading_noise::position_per_mm * e.length_mm +
         noise_heading_deg(e) / deg_per_rad * 0.5 * e.length_mm;
}

/// Empty when `reading` can be the run's stop; else what is off.
std::string problem_of(const ReadingFacts& f, const SessionPose& reading) {
  if (f.heading_needed && !reading.theta_deg) {
    return "this run needs the heading (the third number, degrees, counter-clockwise positive)";
  }
  const Residual r = residual(reading, f.odom);
  const double off_mm = std::hypot(r.x_mm, r.y_mm);
  if (f.allowance) {
    if (off_mm > f.allowance->position_mm) {
      return fmt::format(
          "the stop point {:.1f}, {:.1f} mm is {:.0f} mm from where the odometry says the robot "
          "stopped ({:.1f}, {:.1f} mm); this run can end at most {:.0f} mm from it",
          reading.x_mm, reading.y_mm, off_mm, f.odom.x_mm, f.odom.y_mm, f.allowance->position_mm);
    }
    if (r.theta_deg && std::fabs(*r.theta_deg) > f.allowance->heading_deg) {
      return fmt::format(
          "the heading {:.1f} deg is {:.1f} deg from the odometry's ({:.1f} deg); this run can "
          "end at most {:.1f} deg from it",
          *reading.theta_deg, std::fabs(*r.theta_deg), *f.odom.theta_deg, f.allowance->heading_deg);
    }
  }
  // Beyond half a turn (and the odometry's own wrap and noise: 200 degrees): the same direction
  // as a heading a turn less, typed from another count of turns.
  if (reading.theta_deg && std::fabs(*reading.theta_deg) > max_typed_heading_deg) {
    return fmt::format(
        "the heading {:.1f} deg is more than half a turn (headings are typed from -180 to 180)",
        *reading.theta_deg);
  }
  // The same run driven before: its stop differs from this one's by the noise, or (a calibration
  // applied between them) by at most what that calibration corrected. An earlier reading is not
  // right because it came first: this one is questioned only when it is off from two or more of
  // them (one earlier reading alone cannot tell which of the two is off).
  std::size_t off = 0;
  std::string first_off;
  for (const EarlierReading& e : f.earlier) {
    const Residual before = residual(e.measured, e.odom);
    const double share = e.same_factors ? 0.0 : 1.0;
    const double allow_mm =
        2.0 * noise_position_mm(f.extent) + share * std::hypot(before.x_mm, before.y_mm);
    const double apart_mm = std::hypot(r.x_mm - before.x_mm, r.y_mm - before.y_mm);
    std::string why;
    if (apart_mm > allow_mm) {
      why = fmt::format(
          "it is {:.0f} mm from where the same run stopped before ({}), measured against the "
          "odometry; repeats differ by at most {:.0f} mm",
          apart_mm, pose_text(e.measured), allow_mm);
    } else if (r.theta_deg && before.theta_deg) {
      const double allow_deg =
          2.0 * noise_heading_deg(f.extent) + share * std::fabs(*before.theta_deg);
      const double apart_deg = std::fabs(std::remainder(*r.theta_deg - *before.theta_deg, 360.0));
      if (apart_deg > allow_deg) {
        why = fmt::format(
            "its heading is {:.1f} deg from the same run's before ({:.1f} deg), measured against "
            "the odometry; repeats differ by at most {:.1f} deg",
            apart_deg, *e.measured.theta_deg, allow_deg);
      }
    }
    if (!why.empty()) {
      ++off;
      if (first_off.empty()) {
        first_off = why;
      }
    }
  }
  if (off >= 2 && 2 * off > f.earlier.size()) {
    return first_off;
  }
  return std::string();
}

/// The reading typed with a decimal comma read as a decimal point ("12,5 3" -> 12.5 3), when the
/// line has a comma between two digits; nullopt otherwise.
std::optional<SessionPose> decimal_comma(const std::string& typed) {
  std::string fixed = typed;
  bool changed = false;
  for (std::size_t i = 1; i + 1 < fixed.size(); ++i) {
    if (fixed[i] == ',' && std::isdigit(static_cast<unsigned char>(fixed[i - 1])) != 0 &&
        std::isdigit(static_cast<unsigned char>(fixed[i + 1])) != 0) {
      fixed[i] = '.';
      changed = true;
    }
  }
  SessionPose pose;
  std::string why;
  if (!changed || !parse_measurement_line(fixed, pose, why)) {
    return std::nullopt;
  }
  return pose;
}

/// A slip a person makes reading a tape or typing it, and the reading it would have been.
struct Slip {
  const char* what;
  std::function<std::optional<SessionPose>(const SessionPose&, const ReadingFacts&)> undo;
};

const std::vector<Slip>& slips() {
  static const std::vector<Slip> list = {
      {"the heading's sign",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         if (!p.theta_deg || *p.theta_deg == 0.0) {
           return std::nullopt;
         }
         SessionPose q = p;
         q.theta_deg = -*p.theta_deg;
         return q;
       }},
      {"a heading a whole turn off",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         if (!p.theta_deg || std::fabs(*p.theta_deg) <= max_typed_heading_deg) {
           return std::nullopt;
         }
         SessionPose q = p;
         q.theta_deg = std::remainder(*p.theta_deg, 360.0);
         return q;
       }},
      {"x and y swapped",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{p.y_mm, p.x_mm, p.theta_deg};
       }},
      {"x and y swapped, and the sign of y",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{p.y_mm, -p.x_mm, p.theta_deg};
       }},
      {"x and y swapped, and the sign of x",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{-p.y_mm, p.x_mm, p.theta_deg};
       }},
      {"the sign of y (y is positive to the left)",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{p.x_mm, -p.y_mm, p.theta_deg};
       }},
      {"the sign of x (x is positive ahead)",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{-p.x_mm, p.y_mm, p.theta_deg};
       }},
      {"metres for millimetres",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{1e3 * p.x_mm, 1e3 * p.y_mm, p.theta_deg};
       }},
      {"centimetres for millimetres",
       [](const SessionPose& p, const ReadingFacts&) -> std::optional<SessionPose> {
         return SessionPose{10.0 * p.x_mm, 10.0 * p.y_mm, p.theta_deg};
       }},
      {"the difference from the odometry typed instead of the stop point",
       [](const SessionPose& p, const ReadingFacts& f) -> std::optional<SessionPose> {
         SessionPose q{f.odom.x_mm + p.x_mm, f.odom.y_mm + p.y_mm, p.theta_deg};
         if (p.theta_deg && f.odom.theta_deg) {
           q.theta_deg = std::remainder(*f.odom.theta_deg + *p.theta_deg, 360.0);
         }
         return q;
       }},
  };
  return list;
}

}  // namespace

PathExtent extent_of(const drive::Path& path) {
  PathExtent e;
  for (std::uint8_t i = 0; i < path.count; ++i) {
    e.length_mm += 1e3 * std::fabs(static_cast<double>(path.segments[i].distance_m));
    e.turned_deg += deg_per_rad * std::fabs(static_cast<double>(path.segments[i].angle_rad));
  }
  return e;
}

ReadingAllowance allowance_of(const drive::Path& path,
                              const drive::model::Geometry<double>& in_force_mm) {
  const drive::model::PoseOf<double> planned = end_with(path, in_force_mm, 1.0, 1.0, 1.0);
  ReadingAllowance reach;
  for (const double s : {-reading_box::scale, 0.0, reading_box::scale}) {
    for (const double d : {-reading_box::ratio, 0.0, reading_box::ratio}) {
      for (const double e : {-reading_box::wheelbase, 0.0, reading_box::wheelbase}) {
        const drive::model::PoseOf<double> p =
            end_with(path, in_force_mm, 1.0 + s - 0.5 * d, 1.0 + s + 0.5 * d, 1.0 + e);
        reach.position_mm =
            std::max(reach.position_mm, std::hypot(p.x - planned.x, p.y - planned.y));
        reach.heading_deg =
            std::max(reach.heading_deg, deg_per_rad * std::fabs(p.theta - planned.theta));
      }
    }
  }
  PathExtent extent = extent_of(path);
  extent.wheelbase_mm = in_force_mm.wheelbase;
  reach.position_mm += noise_position_mm(extent);
  reach.heading_deg += noise_heading_deg(extent);
  return reach;
}

std::vector<SlipCandidate> slip_candidates(const SessionPose& reading, const std::string& typed,
                                           const SessionPose& odom) {
  std::vector<SlipCandidate> out;
  const std::optional<SessionPose> comma = decimal_comma(typed);
  if (comma) {
    out.push_back({"a comma for a decimal point", *comma});
  }
  ReadingFacts facts;
  facts.odom = odom;
  for (const auto& [base_what, base] :
       {std::pair<std::string, std::optional<SessionPose>>{"", reading},
        std::pair<std::string, std::optional<SessionPose>>{"a comma for a decimal point, and ",
                                                           comma}}) {
    if (!base) {
      continue;
    }
    for (const Slip& slip : slips()) {
      const std::optional<SessionPose> undone = slip.undo(*base, facts);
      if (undone) {
        out.push_back({base_what + slip.what, *undone});
      }
    }
  }
  return out;
}

std::string comma_note(const std::string& typed, const SessionPose& read) {
  if (typed.find(',') == std::string::npos) {
    return std::string();
  }
  std::string note =
      fmt::format("read as x {}, y {}", number_text(read.x_mm, typed_decimals(typed)),
                  number_text(read.y_mm, typed_decimals(typed)));
  if (read.theta_deg) {
    note += fmt::format(", heading {}", number_text(*read.theta_deg, typed_decimals(typed)));
  }
  note += " (a comma separates numbers here; '.' is the decimal point)";
  if (const std::optional<SessionPose> comma = decimal_comma(typed)) {
    note += fmt::format(": did you mean {}?", pose_text(*comma, typed_decimals(typed)));
  }
  return note;
}

ReadingVerdict judge_reading(const ReadingFacts& facts, const SessionPose& reading,
                             const std::string& typed) {
  ReadingVerdict verdict;
  verdict.decimals = typed.empty() ? decimals_of(reading) : typed_decimals(typed);
  const std::string problem = problem_of(facts, reading);
  if (problem.empty()) {
    return verdict;
  }
  verdict.plausible = false;
  verdict.problem = problem;
  if (facts.heading_needed && !reading.theta_deg) {
    return verdict;  // nothing to explain: a number is missing
  }
  // The slips that would explain it: a decimal comma read as a separator alone, one slip, or a
  // decimal comma and one slip.
  if (decimal_comma(typed)) {
    verdict.comma = "a comma between digits separates numbers here ('.' is the decimal point)";
  }
  for (const SlipCandidate& slip : slip_candidates(reading, typed, facts.odom)) {
    if (problem_of(facts, slip.reading).empty()) {
      verdict.likely = slip.what;
      verdict.suggestion = slip.reading;
      return verdict;
    }
  }
  return verdict;
}

}  // namespace odocal::host::session

namespace odocal::host {

std::string ReadingVerdict::explained() const {
  if (plausible) {
    return std::string();
  }
  std::string text = "  Check this reading: " + problem + ".\n";
  if (!comma.empty()) {
    text += "  Note: " + comma + ".\n";
  }
  if (suggestion) {
    text += "  Likely " + likely + ": did you mean " + session::pose_text(*suggestion, decimals) +
            "?\n";
  } else if (!likely.empty()) {
    text += "  Likely " + likely + ".\n";
  } else {
    text +=
        "  No single slip (a sign, x and y swapped, metres, a decimal comma) explains it: "
        "measure again.\n";
  }
  return text;
}

}  // namespace odocal::host

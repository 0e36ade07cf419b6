// Console commands of the on-robot calibrations: umbmark (UMBmark, seed 002 section 6) and
// lateral (Maddahi eq. 4-5).

#include <numbers>

#include "odocal/console/console.hpp"

namespace odocal::console {
namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// Each group's factors in the order its commands take them: the wheel group (UMBmark applies the
// first three; `fit apply` all four, the arc wheelbase 0 when not given), then the lateral group.
// One table: one address to load for either group.
constexpr params::ParamId kFactorIds[] = {
    params::ParamId::c_l,          params::ParamId::c_r,
    params::ParamId::wheelbase_mm, params::ParamId::wheelbase_arc_mm,
    params::ParamId::f_lat,        params::ParamId::f_lon};
constexpr std::size_t kLateralFirst = 4u;

// The table holds each group of the parameter list, and only it.
constexpr std::size_t group_size(drive::FactorGroup group) {
  std::size_t n = 0u;
  for (const drive::ConfigField& field : drive::config_fields) {
    n += field.group == group ? 1u : 0u;
  }
  return n;
}
constexpr bool ids_in_groups() {
  for (std::size_t i = 0; i < sizeof kFactorIds / sizeof kFactorIds[0]; ++i) {
    const auto group = i < kLateralFirst ? drive::FactorGroup::wheel : drive::FactorGroup::lateral;
    if (drive::config_fields[static_cast<std::size_t>(kFactorIds[i])].group != group) {
      return false;
    }
  }
  return group_size(drive::FactorGroup::wheel) == kLateralFirst &&
         group_size(drive::FactorGroup::lateral) ==
             sizeof kFactorIds / sizeof kFactorIds[0] - kLateralFirst;
}
static_assert(ids_in_groups(), "kFactorIds lists each factor group of drive_config.hpp, whole");

}  // namespace

const params::ParamId* Console::factor_ids(FactorGroup group) {
  return kFactorIds + (group == FactorGroup::wheel ? 0u : kLateralFirst);
}

bool Console::point_args(const Token* words, float& x, float& y) {
  return number_arg(words[0], -1.0e6f, 1.0e6f, x) && number_arg(words[1], -1.0e6f, 1.0e6f, y);
}

void Console::cmd_umbmark_clear() {
  umbmark_.clear();
  send_line("ok cw=%u ccw=%u", 0u, 0u);  // the spec of `umbmark add`
}

void Console::cmd_umbmark_add(const Token* words) {
  const bool cw = words[2].is("cw");
  if (!cw && !words[2].is("ccw")) {
    send_usage(ErrorCode::bad_argument);
    return;
  }
  float x = 0.0f;
  float y = 0.0f;
  if (!point_args(words + 3, x, y)) {
    return;
  }
  if (!umbmark_.add(cw, calib::UmbmarkSession::Error{x, y})) {
    send_error(ErrorCode::umbmark_full, "16 runs per direction at most");
    return;
  }
  send_line("ok cw=%u ccw=%u", umbmark_.cw_count(), umbmark_.ccw_count());
}

void Console::cmd_umbmark_side(const Token* words) {
  float side_m = 0.0f;
  if (!number_arg(words[2], 0.01f, 20.0f, side_m)) {
    return;
  }
  umbmark_.set_side_mm(side_m * 1000.0f);
  send_line("ok side_mm=%3", umbmark_.side_mm());
}

void Console::cmd_umbmark_solve(const Token* words, std::size_t count) {
  const bool exact = count == 3u;
  if (exact && !words[2].is("exact")) {
    send_usage(ErrorCode::bad_argument);
    return;
  }
  const calib::UmbmarkStatus status =
      umbmark_.solve(settings_.get(params::ParamId::wheelbase_mm), exact);
  if (status != calib::UmbmarkStatus::ok) {
    send_error(ErrorCode::umbmark_failed, calib::to_string(status));
    return;
  }
  const calib::UmbmarkSession::Result& result = umbmark_.result();
  send_line(
      "ok e_d=%6 e_b=%6 c_l=%6 c_r=%6 wheelbase_new_mm=%3 alpha_deg=%6 beta_deg=%6"
      " e_max_syst_mm=%3 sem_mm=%3 second_pass_recommended=%u side_mm=%3 runs=%u method=%s",
      result.e_d, result.e_b, result.c_l, result.c_r, result.wheelbase_new_mm, result.alpha_deg,
      result.beta_deg, result.e_max_syst_mm, result.sem_mm,
      result.second_pass_recommended ? 1u : 0u, umbmark_.side_mm(),
      umbmark_.cw_count() + umbmark_.ccw_count(),
      params::method_name(exact ? params::FactorMethod::umbmark_exact
                                : params::FactorMethod::umbmark));
}

void Console::cmd_lateral_clear() {
  lateral_.clear();
  send_line("ok lateral=0");
}

void Console::cmd_lateral_add(const Token* words) {
  float x = 0.0f;
  float y = 0.0f;
  if (!point_args(words + 2, x, y)) {
    return;
  }
  // The stop point belongs to the latest trial, which must be a straight line not used yet:
  // its left-wheel counts give θ_L (eq. 4).
  const KeptTrial* trial = trials_.latest();
  if (trial == nullptr || trial->path != drive::PathId::line) {
    send_error(ErrorCode::no_trial, "latest trial is no line");
    return;
  }
  if (trial->number == lateral_used_) {
    send_error(ErrorCode::no_trial, "latest line trial added already");
    return;
  }
  const float counts_per_rev = settings_.get(params::ParamId::counts_per_rev);
  const float theta_l = kTwoPi * static_cast<float>(trial->count_l) / counts_per_rev;
  const calib::LateralSession::AddStatus added =
      lateral_.add(calib::LateralSession::Stop{x, y}, trial->length_m * 1000.0f, theta_l);
  switch (added) {
    case calib::LateralSession::AddStatus::ok:
      break;
    case calib::LateralSession::AddStatus::full:
      send_error(ErrorCode::lateral_full, "32 trials at most");
      return;
    case calib::LateralSession::AddStatus::length_mismatch:
      send_error(ErrorCode::bad_argument, "length differs from earlier trials");
      return;
    case calib::LateralSession::AddStatus::bad_trial:
      send_error(ErrorCode::no_trial, "the left wheel ran backwards");
      return;
  }
  lateral_used_ = trial->number;
  send_line("ok lateral=%u trial=%u length_mm=%3 theta_l_rad=%6", lateral_.count(), trial->number,
            lateral_.length_mm(), theta_l);
}

void Console::cmd_lateral_solve() {
  // The drive's kinematics already use c_l, c_r and f_lat: eq. 4 is solved for what remains,
  // with equal diameters, and `apply` composes the result with the factors in force.
  const float diameter = settings_.get(params::ParamId::wheel_diameter_mm);
  const calib::LateralStatus status =
      lateral_.solve(settings_.get(params::ParamId::wheelbase_mm), diameter, diameter);
  if (status != calib::LateralStatus::ok) {
    send_error(ErrorCode::lateral_failed, calib::to_string(status));
    return;
  }
  const calib::LateralSession::Result& result = lateral_.result();
  send_line("ok f_lat=%6 f_lon=%6 theta_l_rad=%6 length_mm=%3 trials=%u method=maddahi",
            result.f_lat, result.f_lon, result.theta_l_rad, lateral_.length_mm(), lateral_.count());
}

void Console::cmd_calib_apply(FactorGroup group, const Token* words, std::size_t count) {
  const bool lateral = group == FactorGroup::lateral;
  std::uint32_t date = 0u;
  std::uint16_t runs = static_cast<std::uint16_t>(
      lateral ? lateral_.count() : umbmark_.cw_count() + umbmark_.ccw_count());
  if (!date_arg(words, count, 2u, date, runs)) {
    return;
  }
  if (!(lateral ? lateral_.solved() : umbmark_.solved())) {
    send_error_line(ErrorCode::not_solved, "run %s solve first", lateral ? "lateral" : "umbmark");
    return;
  }
  if (lateral) {
    const calib::LateralSession::Result total =
        calib::compose(calib::LateralSession::Result{settings_.get(params::ParamId::f_lat),
                                                     settings_.get(params::ParamId::f_lon), 0.0f},
                       lateral_.result());
    const float values[] = {total.f_lat, total.f_lon};
    if (apply_factors(FactorGroup::lateral, values, 2u, params::FactorMethod::maddahi, runs, date,
                      0.0f)) {
      lateral_.applied();
    }
    return;
  }
  calib::UmbmarkSession::Factors current;
  current.c_l = settings_.get(params::ParamId::c_l);
  current.c_r = settings_.get(params::ParamId::c_r);
  current.wheelbase_mm = settings_.get(params::ParamId::wheelbase_mm);
  const calib::UmbmarkSession::Factors next = umbmark_.next_factors(current);
  const float values[] = {next.c_l, next.c_r, next.wheelbase_mm};
  const calib::UmbmarkSession::Result& result = umbmark_.result();
  const params::FactorMethod method =
      result.exact ? params::FactorMethod::umbmark_exact : params::FactorMethod::umbmark;
  if (apply_factors(FactorGroup::wheel, values, 3u, method, runs, date,
                    static_cast<float>(result.e_max_syst_mm))) {
    umbmark_.applied();
  }
}

void Console::cmd_host_factors(FactorGroup group, const Token* words, std::size_t count) {
  const bool fit = group == FactorGroup::wheel;
  // Every value is checked against its parameter's range before anything changes.
  const params::ParamId* ids = factor_ids(group);
  const std::size_t id_count = fit ? 3u : 2u;
  // values[3]: `fit apply`'s arc wheelbase, 0 (one wheelbase) unless `arc <mm>` ends the line.
  float values[4] = {};
  if (fit && count > 6u && words[count - 2u].is("arc")) {
    count -= 2u;
    const params::ParamInfo& info = params::param_info(params::ParamId::wheelbase_arc_mm);
    if (!number_arg(words[count + 1u], info.min, info.max, values[3])) {
      return;
    }
  } else if (count > 4u + id_count) {  // `lateral set` ends at runs, `fit apply` at `arc <mm>`
    send_usage(ErrorCode::wrong_arity);
    return;
  }
  for (std::size_t i = 0; i < id_count; ++i) {
    const params::ParamInfo& info = params::param_info(ids[i]);
    if (!number_arg(words[2u + i], info.min, info.max, values[i])) {
      return;
    }
  }
  std::uint32_t date = 0u;
  std::uint16_t runs = 0u;
  if (!date_arg(words, count, 2u + id_count, date, runs)) {
    return;
  }
  const params::FactorMethod method =
      fit ? params::FactorMethod::fit : params::FactorMethod::bootstrap;
  (void)apply_factors(group, values, id_count + (fit ? 1u : 0u), method, runs, date, 0.0f);
}

bool Console::apply_factors(FactorGroup group, const float* values, std::size_t count,
                            params::FactorMethod method, std::uint16_t runs, std::uint32_t date,
                            float quality_mm) {
  if (refuse_busy(Busy::motion)) {
    return false;
  }
  const bool wheel = group == FactorGroup::wheel;
  const params::ParamId* ids = factor_ids(group);
  params::ParamSet candidate = settings_.values();
  for (std::size_t i = 0; i < count; ++i) {
    candidate.set(ids[i], values[i]);
  }
  if (!params::all_in_range(candidate)) {
    send_error(ErrorCode::out_of_range, "factors out of range");
    return false;
  }
  params::Provenance& provenance = wheel ? candidate.wheel : candidate.lateral;
  provenance.method = method;
  provenance.runs = runs;
  provenance.date_unix_s = date;
  provenance.quality_mm = quality_mm;
  if (!config_accepted(settings_.apply(candidate))) {
    return false;
  }
  // The `ok` line: the factors in force, then their provenance (no runs for factors computed on
  // a host).
  ReplyLine reply(out_);
  reply.text("ok");
  for (std::size_t i = 0; i < count; ++i) {
    append(reply, " %s=%6", params::param_info(ids[i]).name, settings_.get(ids[i]));
  }
  // Factors computed on a host print runs only when the host said how many.
  append_either(reply, runs != 0u ? Spec::full : Spec::shorter, " method=%s runs=%u unsaved=1",
                " method=%s unsaved=1", params::method_name(method), runs);
  send(reply);
  return true;
}

}  // namespace odocal::console

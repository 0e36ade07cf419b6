// Console commands of the on-robot calibrations: umbmark (UMBmark, seed 002 section 6) and
// lateral (Maddahi eq. 4-5).

#include "odocal/console/console.hpp"

namespace odocal::console {
namespace {

constexpr int kFactorDecimals = 6;
constexpr int kLengthDecimals = 3;
constexpr float kTwoPi = 6.28318530717958647692f;

constexpr params::ParamId kWheelIds[] = {params::ParamId::c_l, params::ParamId::c_r,
                                         params::ParamId::wheelbase_mm};
constexpr params::ParamId kLateralIds[] = {params::ParamId::f_lat, params::ParamId::f_lon};

}  // namespace

void Console::cmd_umbmark_clear() {
  umbmark_.clear();
  OkLine reply(out_);
  reply.pair_u("cw", 0u).pair_u("ccw", 0u);
  send(reply);
}

void Console::cmd_umbmark_add(const Token* words) {
  const bool cw = words[2].is("cw");
  if (!cw && !words[2].is("ccw")) {
    send_usage(ErrorCode::bad_argument);
    return;
  }
  float x = 0.0f;
  float y = 0.0f;
  if (!number_arg(words[3], -1.0e6f, 1.0e6f, x) || !number_arg(words[4], -1.0e6f, 1.0e6f, y)) {
    return;
  }
  if (!umbmark_.add(cw, calib::UmbmarkSession::Error{x, y})) {
    send_error(ErrorCode::umbmark_full, "16 runs per direction at most");
    return;
  }
  OkLine reply(out_);
  reply.pair_u("cw", umbmark_.cw_count()).pair_u("ccw", umbmark_.ccw_count());
  send(reply);
}

void Console::cmd_umbmark_side(const Token* words) {
  float side_m = 0.0f;
  if (!number_arg(words[2], 0.01f, 20.0f, side_m)) {
    return;
  }
  umbmark_.set_side_mm(side_m * 1000.0f);
  OkLine reply(out_);
  reply.pair("side_mm", umbmark_.side_mm(), kLengthDecimals);
  send(reply);
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
  OkLine reply(out_);
  reply.pair("e_d", result.e_d, kFactorDecimals)
      .pair("e_b", result.e_b, kFactorDecimals)
      .pair("c_l", result.c_l, kFactorDecimals)
      .pair("c_r", result.c_r, kFactorDecimals)
      .pair("wheelbase_new_mm", result.wheelbase_new_mm, kLengthDecimals)
      .pair("alpha_deg", result.alpha_deg, kFactorDecimals)
      .pair("beta_deg", result.beta_deg, kFactorDecimals)
      .pair("e_max_syst_mm", result.e_max_syst_mm, kLengthDecimals)
      .pair("sem_mm", result.sem_mm, kLengthDecimals)
      .pair_u("second_pass_recommended", result.second_pass_recommended ? 1u : 0u)
      .pair("side_mm", umbmark_.side_mm(), kLengthDecimals)
      .pair_u("runs", umbmark_.cw_count() + umbmark_.ccw_count())
      .pair_s("method", exact ? "umbmark-exact" : "umbmark");
  send(reply);
}

void Console::cmd_umbmark_apply(const Token* words, std::size_t count) {
  std::uint32_t date = 0u;
  if (!date_arg(words, count, 2u, date)) {
    return;
  }
  if (!umbmark_.solved()) {
    send_error(ErrorCode::not_solved, "run umbmark solve first");
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
  if (!apply_factors(kWheelIds, values, 3u, method,
                     static_cast<std::uint16_t>(umbmark_.cw_count() + umbmark_.ccw_count()), date,
                     static_cast<float>(result.e_max_syst_mm))) {
    return;
  }
  umbmark_.applied();
  send_factors_applied(kWheelIds, 3u, method, true);
}

void Console::cmd_lateral_clear() {
  lateral_.clear();
  OkLine reply(out_);
  reply.pair_u("lateral", 0u);
  send(reply);
}

void Console::cmd_lateral_add(const Token* words) {
  float x = 0.0f;
  float y = 0.0f;
  if (!number_arg(words[2], -1.0e6f, 1.0e6f, x) || !number_arg(words[3], -1.0e6f, 1.0e6f, y)) {
    return;
  }
  // The stop point belongs to the latest trial, which must be a straight line not used yet:
  // its left-wheel counts give θ_L (eq. 4).
  const KeptTrial* trial = trials_.latest();
  if (trial == nullptr || trial->path != drive::PathId::line) {
    send_error(ErrorCode::no_trial, "latest trial is no line (run line <m>)");
    return;
  }
  if (trial->number == lateral_used_) {
    send_error(ErrorCode::no_trial, "the latest line trial was added already");
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
      send_error(ErrorCode::bad_argument, "line length differs from earlier trials");
      return;
    case calib::LateralSession::AddStatus::bad_trial:
      send_error(ErrorCode::no_trial, "the line turned the left wheel backwards");
      return;
  }
  lateral_used_ = trial->number;
  OkLine reply(out_);
  reply.pair_u("lateral", lateral_.count())
      .pair_u("trial", trial->number)
      .pair("length_mm", lateral_.length_mm(), kLengthDecimals)
      .pair("theta_l_rad", theta_l, kFactorDecimals);
  send(reply);
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
  OkLine reply(out_);
  reply.pair("f_lat", result.f_lat, kFactorDecimals)
      .pair("f_lon", result.f_lon, kFactorDecimals)
      .pair("theta_l_rad", result.theta_l_rad, kFactorDecimals)
      .pair("length_mm", lateral_.length_mm(), kLengthDecimals)
      .pair_u("trials", lateral_.count())
      .pair_s("method", "maddahi");
  send(reply);
}

void Console::cmd_lateral_apply(const Token* words, std::size_t count) {
  std::uint32_t date = 0u;
  if (!date_arg(words, count, 2u, date)) {
    return;
  }
  if (!lateral_.solved()) {
    send_error(ErrorCode::not_solved, "run lateral solve first");
    return;
  }
  const calib::LateralSession::Result& result = lateral_.result();
  const float values[] = {settings_.get(params::ParamId::f_lat) * result.f_lat,
                          settings_.get(params::ParamId::f_lon) * result.f_lon};
  if (!apply_factors(kLateralIds, values, 2u, params::FactorMethod::maddahi,
                     static_cast<std::uint16_t>(lateral_.count()), date, 0.0f)) {
    return;
  }
  lateral_.applied();
  send_factors_applied(kLateralIds, 2u, params::FactorMethod::maddahi, true);
}

void Console::cmd_host_factors(bool fit, const Token* words, std::size_t count) {
  // Every value is checked against its parameter's range before anything changes.
  const params::ParamId* ids = fit ? kWheelIds : kLateralIds;
  const std::size_t id_count = fit ? 3u : 2u;
  float values[3] = {};
  for (std::size_t i = 0; i < id_count; ++i) {
    const params::ParamInfo& info = params::param_info(ids[i]);
    if (!number_arg(words[2u + i], info.min, info.max, values[i])) {
      return;
    }
  }
  std::uint32_t date = 0u;
  if (!date_arg(words, count, 2u + id_count, date)) {
    return;
  }
  const params::FactorMethod method =
      fit ? params::FactorMethod::fit : params::FactorMethod::bootstrap;
  if (apply_factors(ids, values, id_count, method, 0u, date, 0.0f)) {
    send_factors_applied(ids, id_count, method, false);
  }
}

bool Console::apply_factors(const params::ParamId* ids, const float* values, std::size_t count,
                            params::FactorMethod method, std::uint16_t runs, std::uint32_t date,
                            float quality_mm) {
  if (refuse_busy(false)) {
    return false;
  }
  params::ParamSet candidate = settings_.values();
  for (std::size_t i = 0; i < count; ++i) {
    candidate.set(ids[i], values[i]);
  }
  const bool wheel = ids == kWheelIds;
  if (!params::all_in_range(candidate)) {
    send_error(ErrorCode::out_of_range, "factors out of range; not applied");
    return false;
  }
  params::Provenance& provenance = wheel ? candidate.wheel : candidate.lateral;
  provenance.method = method;
  provenance.runs = runs;
  provenance.date_unix_s = date;
  provenance.quality_mm = quality_mm;
  return config_accepted(settings_.apply(candidate));
}

void Console::send_factors_applied(const params::ParamId* ids, std::size_t id_count,
                                   params::FactorMethod method, bool runs) {
  const params::ParamSet& values = settings_.values();
  OkLine reply(out_);
  for (std::size_t i = 0; i < id_count; ++i) {
    reply.pair(params::param_info(ids[i]).name, values.get(ids[i]), kFactorDecimals);
  }
  reply.pair_s("method", params::method_name(method));
  if (runs) {
    reply.pair_u("runs", ids == kWheelIds ? values.wheel.runs : values.lateral.runs);
  }
  reply.pair_u("unsaved", 1u);
  send(reply);
}

}  // namespace odocal::console

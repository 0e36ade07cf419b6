// Console commands of the on-robot calibrations: umbmark (UMBmark, seed 002 section 6) and
// lateral (Maddahi eq. 4-5).

#include "odocal/console/console.hpp"
#include "odocal/drive/numeric.hpp"

namespace odocal::console {
namespace {

constexpr int kFactorDecimals = 6;
constexpr int kLengthDecimals = 3;
constexpr float kTwoPi = 6.28318530717958647692f;

bool parse_date(const Token* words, std::size_t count, std::uint32_t& date) {
  date = 0u;
  return count < 3u || parse_unsigned(words[2], date);
}

}  // namespace

void Console::cmd_umbmark(const Token* words, std::size_t count) {
  const Token& sub = words[1];
  if (sub.is("clear")) {
    if (count != 2u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark clear");
      return;
    }
    umbmark_.clear();
    ReplyLine reply;
    reply.text("ok").pair_u("cw", 0u).pair_u("ccw", 0u);
    send(reply);
  } else if (sub.is("add")) {
    if (count != 5u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark add cw|ccw <x_mm> <y_mm>");
      return;
    }
    const bool cw = words[2].is("cw");
    if (!cw && !words[2].is("ccw")) {
      send_error(ErrorCode::bad_argument, "direction is cw or ccw");
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
    ReplyLine reply;
    reply.text("ok").pair_u("cw", umbmark_.cw_count()).pair_u("ccw", umbmark_.ccw_count());
    send(reply);
  } else if (sub.is("side")) {
    if (count != 3u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark side <side_m>");
      return;
    }
    float side_m = 0.0f;
    if (!number_arg(words[2], 0.01f, 20.0f, side_m)) {
      return;
    }
    umbmark_.set_side_mm(side_m * 1000.0f);
    ReplyLine reply;
    reply.text("ok").pair("side_mm", umbmark_.side_mm(), kLengthDecimals);
    send(reply);
  } else if (sub.is("solve")) {
    if (count > 3u || (count == 3u && !words[2].is("exact"))) {
      send_error(count > 3u ? ErrorCode::wrong_arity : ErrorCode::bad_argument,
                 "usage: umbmark solve [exact]");
      return;
    }
    const bool exact = count == 3u;
    const calib::UmbmarkStatus status =
        umbmark_.solve(settings_.get(params::ParamId::wheelbase_mm), exact);
    if (status != calib::UmbmarkStatus::ok) {
      send_error(ErrorCode::umbmark_failed, calib::to_string(status));
      return;
    }
    const calib::UmbmarkSession::Result& result = umbmark_.result();
    ReplyLine reply;
    reply.text("ok")
        .pair("e_d", result.e_d, kFactorDecimals)
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
  } else if (sub.is("apply")) {
    if (count > 3u) {
      send_error(ErrorCode::wrong_arity, "usage: umbmark apply [unix_s]");
      return;
    }
    std::uint32_t date = 0u;
    if (!parse_date(words, count, date)) {
      send_error(ErrorCode::bad_number, "unix_s is a whole number of seconds");
      return;
    }
    if (!umbmark_.solved()) {
      send_error(ErrorCode::not_solved, "run umbmark solve first");
      return;
    }
    if (moving(loop_.status())) {
      send_error(ErrorCode::busy, "the robot is moving; stop first");
      return;
    }
    calib::UmbmarkSession::Factors current;
    current.c_l = settings_.get(params::ParamId::c_l);
    current.c_r = settings_.get(params::ParamId::c_r);
    current.wheelbase_mm = settings_.get(params::ParamId::wheelbase_mm);
    const calib::UmbmarkSession::Factors next = umbmark_.next_factors(current);
    params::ParamSet candidate = settings_.values();
    candidate.set(params::ParamId::c_l, next.c_l);
    candidate.set(params::ParamId::c_r, next.c_r);
    candidate.set(params::ParamId::wheelbase_mm, next.wheelbase_mm);
    if (!params::all_in_range(candidate)) {
      send_error(ErrorCode::out_of_range, "the factors fall outside their ranges; not applied");
      return;
    }
    const calib::UmbmarkSession::Result& result = umbmark_.result();
    candidate.wheel.method =
        result.exact ? params::FactorMethod::umbmark_exact : params::FactorMethod::umbmark;
    candidate.wheel.runs = static_cast<std::uint16_t>(umbmark_.cw_count() + umbmark_.ccw_count());
    candidate.wheel.date_unix_s = date;
    candidate.wheel.quality_mm = static_cast<float>(result.e_max_syst_mm);
    if (!config_accepted(settings_.apply(candidate))) {
      return;
    }
    umbmark_.applied();
    const params::ParamSet& values = settings_.values();
    ReplyLine reply;
    reply.text("ok")
        .pair("c_l", values.get(params::ParamId::c_l), kFactorDecimals)
        .pair("c_r", values.get(params::ParamId::c_r), kFactorDecimals)
        .pair("wheelbase_mm", values.get(params::ParamId::wheelbase_mm), kFactorDecimals)
        .pair_s("method", params::method_name(values.wheel.method))
        .pair_u("runs", values.wheel.runs)
        .pair_u("unsaved", 1u);
    send(reply);
  } else {
    send_error(ErrorCode::bad_argument, "usage: umbmark clear|add|side|solve|apply");
  }
}

void Console::cmd_lateral(const Token* words, std::size_t count) {
  const Token& sub = words[1];
  if (sub.is("clear")) {
    if (count != 2u) {
      send_error(ErrorCode::wrong_arity, "usage: lateral clear");
      return;
    }
    lateral_.clear();
    ReplyLine reply;
    reply.text("ok").pair_u("lateral", 0u);
    send(reply);
  } else if (sub.is("add")) {
    if (count != 4u) {
      send_error(ErrorCode::wrong_arity, "usage: lateral add <x_mm> <y_mm>");
      return;
    }
    float x = 0.0f;
    float y = 0.0f;
    if (!number_arg(words[2], -1.0e6f, 1.0e6f, x) || !number_arg(words[3], -1.0e6f, 1.0e6f, y)) {
      return;
    }
    // The stop point belongs to the latest trial, which must be a straight line not used yet:
    // its left-wheel counts give θ_L (eq. 4).
    const drive::TrialRecord* trial = trials_.latest();
    if (trial == nullptr || trial->path != drive::PathId::line) {
      send_error(ErrorCode::no_trial, "the latest trial is no line (run line <m> first)");
      return;
    }
    if (trial->number == lateral_used_) {
      send_error(ErrorCode::no_trial, "the latest line trial was added already");
      return;
    }
    const float counts_per_rev = settings_.get(params::ParamId::counts_per_rev);
    const float theta_l = kTwoPi * drive::to_float(trial->count_l) / counts_per_rev;
    const calib::LateralSession::AddStatus added =
        lateral_.add(calib::LateralSession::Stop{x, y}, trial->length_m * 1000.0f, theta_l);
    switch (added) {
      case calib::LateralSession::AddStatus::ok:
        break;
      case calib::LateralSession::AddStatus::full:
        send_error(ErrorCode::lateral_full, "32 trials at most");
        return;
      case calib::LateralSession::AddStatus::length_mismatch:
        send_error(ErrorCode::bad_argument, "the line's length differs from the trials entered");
        return;
      case calib::LateralSession::AddStatus::bad_trial:
        send_error(ErrorCode::no_trial, "the line trial turned the left wheel backwards");
        return;
    }
    lateral_used_ = trial->number;
    ReplyLine reply;
    reply.text("ok")
        .pair_u("lateral", lateral_.count())
        .pair_u("trial", trial->number)
        .pair("length_mm", lateral_.length_mm(), kLengthDecimals)
        .pair("theta_l_rad", theta_l, kFactorDecimals);
    send(reply);
  } else if (sub.is("solve")) {
    if (count != 2u) {
      send_error(ErrorCode::wrong_arity, "usage: lateral solve");
      return;
    }
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
    ReplyLine reply;
    reply.text("ok")
        .pair("f_lat", result.f_lat, kFactorDecimals)
        .pair("f_lon", result.f_lon, kFactorDecimals)
        .pair("theta_l_rad", result.theta_l_rad, kFactorDecimals)
        .pair("length_mm", lateral_.length_mm(), kLengthDecimals)
        .pair_u("trials", lateral_.count())
        .pair_s("method", "maddahi");
    send(reply);
  } else if (sub.is("apply")) {
    if (count > 3u) {
      send_error(ErrorCode::wrong_arity, "usage: lateral apply [unix_s]");
      return;
    }
    std::uint32_t date = 0u;
    if (!parse_date(words, count, date)) {
      send_error(ErrorCode::bad_number, "unix_s is a whole number of seconds");
      return;
    }
    if (!lateral_.solved()) {
      send_error(ErrorCode::not_solved, "run lateral solve first");
      return;
    }
    if (moving(loop_.status())) {
      send_error(ErrorCode::busy, "the robot is moving; stop first");
      return;
    }
    const calib::LateralSession::Result& result = lateral_.result();
    params::ParamSet candidate = settings_.values();
    candidate.set(params::ParamId::f_lat, candidate.get(params::ParamId::f_lat) * result.f_lat);
    candidate.set(params::ParamId::f_lon, candidate.get(params::ParamId::f_lon) * result.f_lon);
    if (!params::all_in_range(candidate)) {
      send_error(ErrorCode::out_of_range, "the factors fall outside their ranges; not applied");
      return;
    }
    candidate.lateral.method = params::FactorMethod::maddahi;
    candidate.lateral.runs = static_cast<std::uint16_t>(lateral_.count());
    candidate.lateral.date_unix_s = date;
    candidate.lateral.quality_mm = 0.0f;
    if (!config_accepted(settings_.apply(candidate))) {
      return;
    }
    lateral_.applied();
    const params::ParamSet& values = settings_.values();
    ReplyLine reply;
    reply.text("ok")
        .pair("f_lat", values.get(params::ParamId::f_lat), kFactorDecimals)
        .pair("f_lon", values.get(params::ParamId::f_lon), kFactorDecimals)
        .pair_s("method", "maddahi")
        .pair_u("runs", values.lateral.runs)
        .pair_u("unsaved", 1u);
    send(reply);
  } else if (sub.is("set")) {
    if (count != 4u && count != 5u) {
      send_error(ErrorCode::wrong_arity, "usage: lateral set <f_lat> <f_lon> [unix_s]");
      return;
    }
    constexpr params::ParamId ids[] = {params::ParamId::f_lat, params::ParamId::f_lon};
    apply_host_factors(words, count, 2u, ids, 2u, params::FactorMethod::bootstrap);
  } else {
    send_error(ErrorCode::bad_argument, "usage: lateral clear|add|solve|apply|set");
  }
}

void Console::cmd_fit(const Token* words, std::size_t count) {
  if (!words[1].is("apply")) {
    send_error(ErrorCode::bad_argument, "usage: fit apply <c_l> <c_r> <wheelbase_mm> [unix_s]");
    return;
  }
  constexpr params::ParamId ids[] = {params::ParamId::c_l, params::ParamId::c_r,
                                     params::ParamId::wheelbase_mm};
  apply_host_factors(words, count, 2u, ids, 3u, params::FactorMethod::fit);
}

void Console::apply_host_factors(const Token* words, std::size_t count, std::size_t first,
                                 const params::ParamId* ids, std::size_t id_count,
                                 params::FactorMethod method) {
  // Every value is checked against its parameter's range before anything changes.
  params::ParamSet candidate = settings_.values();
  for (std::size_t i = 0; i < id_count; ++i) {
    const params::ParamInfo& info = params::param_info(ids[i]);
    float value = 0.0f;
    if (!number_arg(words[first + i], info.min, info.max, value)) {
      return;
    }
    candidate.set(ids[i], value);
  }
  std::uint32_t date = 0u;
  if (count > first + id_count && !parse_unsigned(words[first + id_count], date)) {
    send_error(ErrorCode::bad_number, "unix_s is a whole number of seconds");
    return;
  }
  if (!params::all_in_range(candidate)) {
    send_error(ErrorCode::out_of_range, "the factors fall outside their ranges; not applied");
    return;
  }
  if (moving(loop_.status())) {
    send_error(ErrorCode::busy, "the robot is moving; stop first");
    return;
  }
  const bool wheel = method == params::FactorMethod::fit;
  params::Provenance& provenance = wheel ? candidate.wheel : candidate.lateral;
  provenance = params::Provenance{};
  provenance.method = method;
  provenance.date_unix_s = date;
  if (!config_accepted(settings_.apply(candidate))) {
    return;
  }
  send_factors_applied(ids, id_count, method);
}

void Console::send_factors_applied(const params::ParamId* ids, std::size_t id_count,
                                   params::FactorMethod method) {
  ReplyLine reply;
  reply.text("ok");
  for (std::size_t i = 0; i < id_count; ++i) {
    reply.pair(params::param_info(ids[i]).name, settings_.get(ids[i]), kFactorDecimals);
  }
  reply.pair_s("method", params::method_name(method)).pair_u("unsaved", 1u);
  send(reply);
}

}  // namespace odocal::console

// The console's asynchronous lines, written from `poll` between commands: listings (`help`,
// `params`, `trials`) a line at a time, `# done trial=` announcements, and the periodic streams.

#include "odocal/console/console.hpp"
#include "odocal/math/numeric.hpp"

namespace odocal::console {

void Console::start_listing(Listing listing) {
  listing_ = listing;
  listing_index_ = 0u;
  continue_listing();
}

void Console::continue_listing() {
  while (listing_ != Listing::none && out_.free_space() >= max_reply + 2u) {
    ReplyLine line(out_);
    if (listing_ == Listing::help) {
      // One line per form, then the target's own command.
      const char* text = nullptr;
      if (listing_index_ < command_form_count) {
        text = command_forms[listing_index_].synopsis;
      } else if (listing_index_ == command_form_count) {
        text = target_usage();
      }
      if (text != nullptr) {
        ++listing_index_;
        append(line, "# %s", text);
        send(line);
        continue;
      }
      append(line, "ok commands=%u", listing_index_);  // the number of help lines
    } else if (listing_ == Listing::params) {
      if (listing_index_ < params::param_count) {
        const auto id = static_cast<params::ParamId>(listing_index_++);
        const params::ParamInfo& info = params::param_info(id);
        append(line, "# %s=%6 unit=%s min=%6 max=%6 default=%6", info.name, settings_.get(id),
               info.unit, info.min, info.max, settings_.default_value(id));
        send(line);
        continue;
      }
      append(line, "ok params=%u unsaved=%u", params::param_count, settings_.unsaved() ? 1u : 0u);
    } else {
      if (listing_index_ < trials_.size()) {
        const KeptTrial& trial = trials_.at(listing_index_++);
        append(line, "# trial %u", trial.number);
        trial_pairs(line, trial);
        send(line);
        continue;
      }
      append(line, "ok trials=%u", trials_.size());
    }
    send(line);
    listing_ = Listing::none;
  }
}

void Console::note_trials() {
  const drive::TrialRecord trial = loop_.last_trial();
  if (trial.number == 0u || trial.number == trial_seen_) {
    return;
  }
  trial_seen_ = trial.number;
  trials_.push(trial);
  const std::size_t typed = clear_typing();
  ReplyLine line(out_);
  append(line, "# done trial=%u path=%s", trial.number, drive::path_name(trial.path));
  // Announced like a reply (never dropped): a host waits for it.
  send_over_typing(line, typed);
}

namespace {

// Next due instant of a periodic stream; @return false when not due yet.
bool due(std::uint32_t now_us, std::uint32_t period_us, std::uint32_t& next_us) {
  if (static_cast<std::int32_t>(now_us - next_us) < 0) {
    return false;
  }
  next_us += period_us;
  if (static_cast<std::int32_t>(now_us - next_us) >= 0) {
    next_us = now_us + period_us;  // fell behind: skip, do not burst
  }
  return true;
}

}  // namespace

void Console::emit_streams(std::uint32_t now_us) {
  // One path for both streams (odom first): they differ only in their time and values.
  for (std::size_t i = 0u; i < streams_.size(); ++i) {
    StreamTimer& timer = streams_[i];
    if (timer.period_us == 0u || !due(now_us, timer.period_us, timer.next_us)) {
      continue;
    }
    const bool odom = i == 0u;
    drive::Pose pose;
    drive::WheelCounts counts;
    if (odom) {
      pose = loop_.pose();
      counts.t_us = clock_us_;
    } else {
      counts = loop_.wheel_counts();
    }
    const std::size_t mark = out_.size();
    const std::size_t typed = clear_typing();
    ReplyLine line(out_);
    const std::uint64_t t_ms = math::divide_u64(counts.t_us, 1000u);
    if (odom) {
      append(line, "# odom t_ms=%U", &t_ms);
      pose_pairs(line, pose);
    } else {
      append(line, "# ticks t_ms=%U count_l=%I count_r=%I", &t_ms, &counts.left, &counts.right);
      if (ticks_crc_) {
        // What the line says, checked: a host drops a line whose bytes came damaged.
        line.pair_u("crc", crc16(line.data(), line.size()));
      }
    }
    send_async(line, mark, typed);
  }
}

}  // namespace odocal::console

#pragma once
// Internal to the session: every logged run judged by all the others (DESIGN "Readings judged by
// all the runs"; the judgement itself: odocal/host/run_agreement.hpp). The jury holds the runs a
// procedure measured for its fit, checks each reading as it is typed against what the runs before
// it predict, and after each reading settles every run that disagrees with the owner: typed again,
// kept (confirmed by its number), or driven again. A run that disagrees and was not confirmed
// never reaches the fit, the stated precision, target_met or the save question.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/host/run_agreement.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

class RunJury {
 public:
  /// Judges about `centre` (the geometry in force when the session started) for a robot told
  /// `nominal`. Choices recorded by an interrupted session (its `disagreeing_runs`) are taken over
  /// for the runs it replays, when their reading did not change since.
  RunJury(Context& c, const FitNominal& nominal, const FitGeometry& centre);
  RunJury(const RunJury&) = delete;
  RunJury& operator=(const RunJury&) = delete;
  ~RunJury();

  /// The session's run `run_index` (0-based into Context::runs; logged and measured) joins.
  void add(std::size_t run_index);

  /// `base` (the reading's own check) and, where two or more runs can predict it, what they
  /// predict for `r`: a reading far from it is questioned at once, with the likely slip, unless
  /// one earlier run alone makes the difference (then both are shown after the reading, and
  /// neither is the one assumed right).
  [[nodiscard]] ReadingCheck check_for(const RunRecord& r, const ReadingCheck& base) const;

  /// Every run that disagrees with the others, settled: shown (its number, `disagree`, what the
  /// others predict, the likely slip, a run that may be the wrong one instead) and, with a person
  /// at the terminal, retyped, kept or driven again; without one, left out. Returns the runs to
  /// drive again (indexes into Context::runs), in order.
  std::vector<std::size_t> settle();

  /// The logs the fit may use: every run's but those left out.
  [[nodiscard]] std::vector<TickLog> logs_in_use() const;
  /// Context::runs index of each log of logs_in_use(), in order.
  [[nodiscard]] std::vector<std::size_t> runs_in_use() const;
  [[nodiscard]] std::size_t size() const { return runs_.size(); }
  /// Runs left out to be driven again (each followed by another of its kind).
  [[nodiscard]] std::size_t driven_again() const;
  /// `result.run_checks`: every run's reading against what all the others predict for it
  /// (run, label, measured, predicted, sd, off_mm, off_deg, sigmas, status: agrees, disagrees,
  /// kept, left out, driven again).
  [[nodiscard]] nlohmann::json checks() const;
  /// `result.disagreeing_runs`: each run that disagreed, what was shown and what the owner chose.
  [[nodiscard]] const nlohmann::json& record() const { return record_; }

 private:
  struct Member {
    std::size_t run_index = 0;
    TickLog log;
    bool left_out = false;
    bool kept = false;
    bool again = false;  ///< left out to be driven again
  };
  [[nodiscard]] std::vector<TickLog> logs() const;
  [[nodiscard]] std::vector<bool> left_out() const;
  void note(std::size_t member, const std::string& choice, const Disagreement& d,
            const std::string& likely);
  /// What show() said: the slip that explains the run named ("" when none does), and the runs
  /// shown beside it as possibly the wrong one instead (members).
  struct Shown {
    std::string likely;
    std::vector<std::size_t> partners;
  };
  /// Shows `d`: the run alone with what the others predict and the likely slip, or, when runs
  /// contradict each other and nothing else, each of them and the slip that would make it agree.
  Shown show(const Disagreement& d);
  /// Member `member`'s reading typed again (its run or the disagreeing run `disagreeing_run`'s
  /// partner), judged by the other runs.
  void retype(std::size_t member, std::size_t disagreeing_run);

  Context& c_;
  FitNominal nominal_;
  FitGeometry centre_;
  AgreementOptions options_;
  std::vector<Member> runs_;
  nlohmann::json record_ = nlohmann::json::array();
  RunJury* previous_ = nullptr;  ///< Context::jury before this one
};

}  // namespace odocal::host::session

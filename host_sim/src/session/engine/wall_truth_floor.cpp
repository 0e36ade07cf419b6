// `--truth walls` where the walls cannot tell the wheels' scale: the tape that measures the runs
// on an open floor, behind the walls' own MeasurementSource (wall_truth.hpp, docs/maze.md).

#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include "wall_truth.hpp"

namespace odocal::host {
namespace session {

bool WallTruth::to_the_floor() {
  on_floor_ = tape_ != nullptr;
  return on_floor_;
}

bool WallTruth::check_next(const ReadingCheck& check, bool heading_needed) {
  return on_floor_ && tape_->check_next(check, heading_needed);
}

std::optional<std::string> WallTruth::ask(const std::string& question) {
  return on_floor_ ? tape_->ask(question) : std::nullopt;
}

std::optional<SessionPose> WallTruth::retype(const RunRecord& run, std::size_t number,
                                             const ReadingCheck& check, bool heading_needed) {
  // Only a tape's reading is typed again: a look is what the walls said.
  return retypable(number - 1) ? tape_->retype(run, number, check, heading_needed) : std::nullopt;
}

bool WallTruth::retypable(std::size_t index) const {
  return tape_ != nullptr && tape_->by_hand() &&
         std::find(taped_.begin(), taped_.end(), index) != taped_.end();
}

std::size_t WallTruth::tape_readings(std::size_t runs) const {
  return static_cast<std::size_t>(
      std::count_if(taped_.begin(), taped_.end(), [runs](std::size_t i) { return i < runs; }));
}

}  // namespace session

std::unique_ptr<MeasurementSource> wall_measurements(RobotClient& robot, const MazeKnowledge& maze,
                                                     std::ostream& log,
                                                     std::unique_ptr<MeasurementSource> tape) {
  auto walls = std::make_unique<session::WallTruth>(robot, maze, log);
  walls->set_tape(std::move(tape));
  return walls;
}

}  // namespace odocal::host

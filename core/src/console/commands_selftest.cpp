// Console command `selftest`: the wiring self-test (SelfTest, docs/wiring.md), started by the
// command and moved on from `poll` until its one reply.

#include "odocal/console/console.hpp"

namespace odocal::console {

void Console::cmd_selftest(const Token* words, std::size_t count) {
  // `selftest left` / `selftest right`: that wheel alone (the host then measures where the robot
  // went, to tell a reversed motor from a reversed encoder).
  SelfTest::Wheels wheels = SelfTest::Wheels::both;
  if (count == 2u) {
    if (words[1].is("left")) {
      wheels = SelfTest::Wheels::left;
    } else if (words[1].is("right")) {
      wheels = SelfTest::Wheels::right;
    } else {
      send_error(ErrorCode::bad_argument, "selftest [left|right]");
      return;
    }
  }
  if (selftest_.start(wheels, last_now_us_) == SelfTest::Step::refused) {
    send_error(ErrorCode::fault, "faulted; stop acknowledges");
  }
}

void Console::continue_selftest() {
  const SelfTest::Step step = selftest_.advance(last_now_us_);
  if (step == SelfTest::Step::refused) {
    send_error(ErrorCode::fault, "faulted; stop acknowledges");
    return;
  }
  if (step != SelfTest::Step::done) {
    return;
  }
  const std::int32_t* counts = selftest_.counts();
  ReplyLine reply(out_);
  reply.text("ok faults=");
  flag_names(reply, selftest_.faults(), SelfTest::fault_names);
  append(reply, " ll=%i lr=%i rl=%i rr=%i", counts[0], counts[1], counts[2], counts[3]);
  send(reply);
}

}  // namespace odocal::console

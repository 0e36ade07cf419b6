// The console's flow control: it never blocks, reads input only when a reply fits (input waits in
// the stream meanwhile: the console keeps no receive ring), drops stream lines rather than
// replies, and allocates nothing.

#include "odocal/console/console.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <regex>
#include <set>
#include <sstream>

#include "alloc_counter.hpp"
#include "console_rig.hpp"
#include "odocal/calib/umbmark.hpp"
#include "odocal/console/version.hpp"
#include "odocal/params/crc32.hpp"

namespace odocal::test {
namespace {

using console::ConsoleOptions;
using console::EchoMode;

TEST(Console, AFullOutputQueueDropsStreamLinesNeverReplies) {
  auto rig = make_rig();
  rig->reply("stream odom 100");
  rig->stream.write_limit = 0;  // the link stalls (terminal closed, flow control)
  for (int i = 0; i < 5000; ++i) {
    rig->now_us += 1000;
    rig->console.poll(rig->now_us);  // returns every time: nothing blocks
  }
  rig->stream.type("get c_l\n");
  for (int i = 0; i < 10; ++i) {
    rig->now_us += 1000;
    rig->console.poll(rig->now_us);
  }
  rig->stream.write_limit = 1 << 20;
  const std::size_t mark = rig->stream.output_size;
  rig->console.poll(rig->now_us);
  const auto lines = rig->split_lines(mark);
  bool got_reply = false;
  for (const auto& l : lines)
    got_reply = got_reply || l == "ok c_l=1.000000";
  EXPECT_TRUE(got_reply);
  EXPECT_GT(rig->console.counters().stream_dropped, 400u);
  const std::string status = rig->reply("stream off");
  EXPECT_GT(number(value_of(rig->reply("status"), "stream_dropped")), 400.0);
}

TEST(Console, InputWaitsInTheStreamUntilAReplyFitsAndNoneIsLost) {
  auto rig = make_rig();
  rig->stream.write_limit = 0;  // the link stalls: the first reply stays in the output queue
  rig->stream.type("status\nget c_l\nget c_r\n");
  for (int i = 0; i < 50; ++i) {
    rig->now_us += 1000;
    rig->console.poll(rig->now_us);  // returns every time: nothing blocks
  }
  // `status` (over 200 bytes) leaves less room than a whole reply needs: nothing more is read,
  // the rest waits in the stream (the console keeps no receive ring of its own).
  EXPECT_EQ(rig->stream.input_pos, std::string("status\n").size());
  EXPECT_FALSE(rig->console.idle());
  rig->stream.write_limit = 1 << 20;
  rig->settle();
  const auto lines = rig->split_lines(0);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("ok mode=", 0), 0u);
  EXPECT_EQ(lines[1], "ok c_l=1.000000");
  EXPECT_EQ(lines[2], "ok c_r=1.000000");
}

TEST(Console, ALineOfAnyLengthIsReadThroughAndRefusedWhole) {
  auto rig = make_rig();
  rig->stream.type(std::string(400, 'x') + "\nget c_l\n");
  rig->settle();
  const auto lines = rig->split_lines(0);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(error_code(lines[0]), "line_too_long");
  EXPECT_EQ(lines[1], "ok c_l=1.000000");
}

TEST(Console, StatusReportsTheBytesTheStreamLost) {
  auto rig = make_rig();
  EXPECT_EQ(value_of(rig->reply("status"), "rx_dropped"), "0");
  rig->stream.dropped = 7u;  // e.g. the USART's ring overflowed
  EXPECT_EQ(value_of(rig->reply("status"), "rx_dropped"), "7");
  EXPECT_EQ(rig->console.counters().rx_dropped, 7u);
}

TEST(Console, IdleReadsAheadOnlyOnceEverythingBeforeWasAnswered) {
  auto rig = make_rig();
  EXPECT_TRUE(rig->console.idle());
  rig->stream.type("get c_l\n");
  EXPECT_FALSE(rig->console.idle());  // a byte waits (read ahead, kept for poll)
  rig->settle();
  EXPECT_TRUE(rig->stream.drained());
  EXPECT_EQ(rig->split_lines(0), std::vector<std::string>{"ok c_l=1.000000"});
}

TEST(Console, OneCommandPerPollAndReadsOnlyWhenAReplyFits) {
  auto rig = make_rig();
  rig->stream.type("get c_l\nget c_r\n");
  rig->now_us += 100;
  rig->console.poll(rig->now_us);
  EXPECT_EQ(rig->split_lines(0).size(), 1u);
  EXPECT_FALSE(rig->console.idle());
  rig->console.poll(rig->now_us);
  EXPECT_EQ(rig->split_lines(0).size(), 2u);
  EXPECT_TRUE(rig->console.idle());
}

TEST(Console, PollingACommandSessionAllocatesNothing) {
  auto rig = make_rig();
  rig->stream.type(
      "help\nparams\nversion\nstatus\nget c_l\nset c_l 1.01\nsave\nload\ndefaults\nodom\n"
      "odom reset\ndrive 0.1 0 10\nstop\nrun line 1\nstop\numbmark add cw 1 2\numbmark add cw 2 "
      "1\numbmark add ccw 1 2\numbmark add ccw 2 1\numbmark solve\numbmark apply\n"
      "stream odom 50\nbad\nset c_l 1e\nprovenance\n");
  AllocationWatch watch;
  for (int i = 0; i < 20000; ++i) {
    rig->now_us += 100;
    rig->console.poll(rig->now_us);
    if (i % 10 == 0)
      rig->loop.tick(rig->now_us);
  }
  EXPECT_EQ(watch.allocations(), 0u);
  EXPECT_TRUE(rig->stream.drained());
  EXPECT_GE(rig->console.counters().commands, 25u);
}

}  // namespace
}  // namespace odocal::test

// The command list (console/commands.hpp) against what the console does: `help` prints its rows,
// find_form reads lines as the console does, and each form changes no parameter its row does not
// name (a host's copy of the parameters relies on that: host/robot_client.hpp).

#include "odocal/console/commands.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "console_rig.hpp"

namespace odocal::test {
namespace {

using console::Changes;
using console::CommandForm;
using console::FormLookup;

FormLookup lookup_of(const std::string& line) {
  static std::vector<console::Token> words(12);
  const std::size_t count = console::split(line.data(), line.size(), words.data(), words.size());
  return console::find_form(words.data(), count);
}

TEST(CommandList, HelpPrintsEveryRowInOrder) {
  auto rig = make_rig();
  const auto lines = rig->send("help");
  ASSERT_EQ(lines.size(), console::command_form_count + 1u);
  for (std::size_t i = 0; i < console::command_form_count; ++i) {
    EXPECT_EQ(lines[i], std::string("# ") + console::command_forms[i].synopsis);
  }
}

TEST(CommandList, FindFormReadsALineAsTheConsoleDoes) {
  EXPECT_EQ(lookup_of("get c_l").form->handler, console::Handler::get);
  EXPECT_EQ(lookup_of("  umbmark   apply  ").form->handler, console::Handler::umbmark_apply);
  EXPECT_EQ(lookup_of("umbmark apply 1700000000 10").form->handler,
            console::Handler::umbmark_apply);
  EXPECT_EQ(lookup_of("stream ticks 50 crc").form->handler, console::Handler::stream_ticks);
  EXPECT_EQ(lookup_of("trial 3").form->handler, console::Handler::trial);
  EXPECT_EQ(lookup_of("frobnicate").result, FormLookup::Result::unknown);
  EXPECT_EQ(lookup_of("").result, FormLookup::Result::unknown);
  EXPECT_EQ(lookup_of("umbmark").result, FormLookup::Result::wrong_arity);
  EXPECT_EQ(lookup_of("umbmark fly").result, FormLookup::Result::bad_argument);
  EXPECT_EQ(lookup_of("umbmark clear now").result, FormLookup::Result::wrong_arity);
  EXPECT_EQ(lookup_of("umbmark clear now").last - lookup_of("umbmark clear now").first, 1);
  // And the robot refuses what find_form refuses, with the refusal it names.
  auto rig = make_rig();
  EXPECT_EQ(error_code(rig->reply("frobnicate")), "unknown_command");
  EXPECT_EQ(error_code(rig->reply("umbmark")), "wrong_arity");
  EXPECT_EQ(error_code(rig->reply("umbmark fly")), "bad_argument");
  EXPECT_EQ(error_code(rig->reply("umbmark clear now")), "wrong_arity");
}

// The parameters whose values differ between two sets.
std::set<std::size_t> changed(const params::ParamSet& before, const params::ParamSet& after) {
  std::set<std::size_t> ids;
  for (std::size_t i = 0; i < params::param_count; ++i) {
    if (before.values[i] != after.values[i]) {
      ids.insert(i);
    }
  }
  return ids;
}

bool allowed(const CommandForm& form, const std::string& line, std::size_t id) {
  const drive::ConfigField& field = drive::config_fields[id];
  switch (form.changes()) {
    case Changes::nothing:
      return false;
    case Changes::named:
      return line.find(std::string(" ") + field.name + " ") != std::string::npos;
    case Changes::wheel:
      return field.group == drive::FactorGroup::wheel;
    case Changes::lateral:
      return field.group == drive::FactorGroup::lateral;
    case Changes::any:
      return true;
  }
  return false;
}

TEST(CommandList, EveryFormChangesOnlyTheParametersItsRowNames) {
  // One or more lines of every form, in an order that lets the calibrations solve and apply.
  const std::vector<std::string> lines = {"help",
                                          "version",
                                          "status",
                                          "params",
                                          "get c_l",
                                          "provenance",
                                          "set v_max_mps 0.15",
                                          "set c_l 1.01",
                                          "save",
                                          "set c_r 0.99",
                                          "load",
                                          "set c_r 0.98",
                                          "defaults",
                                          "odom",
                                          "odom reset",
                                          "walls",
                                          "drive 0.1 0 50",
                                          "stop",
                                          "selftest",
                                          "stop",
                                          "selftest left",
                                          "stop",
                                          "run line 0.2",
                                          "stop",
                                          "run umbmark-cw 0.5",
                                          "stop",
                                          "run umbmark-ccw 0.5",
                                          "stop",
                                          "run unseen",
                                          "stop",
                                          "trial",
                                          "trial 1",
                                          "trials",
                                          "trials clear",
                                          "umbmark clear",
                                          "umbmark side 4",
                                          "umbmark add cw -20 40",
                                          "umbmark add ccw -30 -10",
                                          "umbmark add cw -24 36",
                                          "umbmark add ccw -26 -14",
                                          "umbmark solve",
                                          "umbmark solve exact",
                                          "umbmark apply",
                                          "lateral clear",
                                          "lateral add 1000 10",
                                          "lateral solve",
                                          "lateral apply",
                                          "lateral set 1.02 0.99",
                                          "lateral set 1.01 0.98 1700000000 10",
                                          "fit apply 1.003 0.997 151.5",
                                          "fit apply 1.002 0.998 151 1700000000 8 arc 152",
                                          "stream odom 10",
                                          "stream ticks 20 crc",
                                          "stream ticks 20",
                                          "stream off",
                                          "echo off",
                                          "echo on",
                                          "echo off"};
  auto rig = make_rig();
  std::set<console::Handler> seen;
  std::set<Changes> changing_kinds;
  for (const std::string& line : lines) {
    const FormLookup lookup = lookup_of(line);
    ASSERT_EQ(lookup.result, FormLookup::Result::found) << line;
    seen.insert(lookup.form->handler);
    const params::ParamSet before = rig->console.params();
    rig->send(line);
    rig->tick(20);
    rig->settle();
    for (const std::size_t id : changed(before, rig->console.params())) {
      EXPECT_TRUE(allowed(*lookup.form, line, id))
          << "`" << line << "` changed " << drive::config_fields[id].name;
      changing_kinds.insert(lookup.form->changes());
    }
  }
  EXPECT_EQ(seen.size(), console::command_form_count) << "a form has no line above";
  // Every kind of change was seen to change something: the rows do not claim too much either.
  for (const Changes kind : {Changes::named, Changes::wheel, Changes::lateral, Changes::any}) {
    EXPECT_EQ(changing_kinds.count(kind), 1u) << static_cast<int>(kind);
  }
}

}  // namespace
}  // namespace odocal::test

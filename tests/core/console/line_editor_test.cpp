#include "odocal/console/line_editor.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace odocal::console {
namespace {

struct Fed {
  std::vector<LineEvent> events;
  std::vector<std::string> lines;
  std::string echo;
};

Fed feed(LineEditor& editor, const std::string& bytes) {
  Fed fed;
  for (char c : bytes) {
    Echo echo;
    const LineEvent event = editor.feed(static_cast<std::uint8_t>(c), echo);
    fed.echo.append(echo.bytes.data(), echo.count);
    if (event != LineEvent::none) {
      fed.events.push_back(event);
      fed.lines.emplace_back(editor.line(), editor.length());
    }
  }
  return fed;
}

TEST(LineEditor, CrLfAndCrLfEachEndOneLine) {
  LineEditor editor;
  const Fed fed = feed(editor, "a\rb\nc\r\nd\n\re\r");
  ASSERT_EQ(fed.events.size(), 6u);
  EXPECT_EQ(fed.lines[0], "a");
  EXPECT_EQ(fed.lines[1], "b");
  EXPECT_EQ(fed.lines[2], "c");  // the LF of CR LF is swallowed
  EXPECT_EQ(fed.lines[3], "d");
  EXPECT_EQ(fed.events[4], LineEvent::empty);  // LF CR is two line ends
  EXPECT_EQ(fed.lines[5], "e");
}

TEST(LineEditor, BackspaceAndDeleteEdit) {
  LineEditor editor;
  const Fed fed = feed(editor, std::string("get c_x\bl\n") + "ab\x7f\x7f\x7f" + "cd\n");
  ASSERT_EQ(fed.events.size(), 2u);
  EXPECT_EQ(fed.lines[0], "get c_l");
  EXPECT_EQ(fed.lines[1], "cd");  // the third DEL on an empty line does nothing
  EXPECT_NE(fed.echo.find("\b \b"), std::string::npos);
  EXPECT_TRUE(editor.saw_terminal());
}

TEST(LineEditor, ExactlyMaxLineIsAcceptedOneMoreIsRefusedWhole) {
  LineEditor editor;
  const std::string max(LineEditor::max_line, 'a');
  Fed fed = feed(editor, max + "\n");
  ASSERT_EQ(fed.events.size(), 1u);
  EXPECT_EQ(fed.events[0], LineEvent::line);
  EXPECT_EQ(fed.lines[0].size(), 127u);
  fed = feed(editor, max + "b" + std::string(500, 'c') + "\nok\n");
  ASSERT_EQ(fed.events.size(), 2u);
  EXPECT_EQ(fed.events[0], LineEvent::too_long);
  EXPECT_EQ(fed.events[1], LineEvent::line);  // the next line is whole again
  EXPECT_EQ(fed.lines[1], "ok");
  // Backspace cannot rescue an over-long line: it is refused whole.
  fed = feed(editor, max + "bb\b\b\n");
  EXPECT_EQ(fed.events[0], LineEvent::too_long);
}

TEST(LineEditor, NonAsciiAndControlBytesMarkTheLineBad) {
  LineEditor editor;
  Fed fed = feed(editor, "get c_\xc3\xa9\nget\x01 x\n\x1b[A\nfine\n");
  ASSERT_EQ(fed.events.size(), 4u);
  EXPECT_EQ(fed.events[0], LineEvent::bad_byte);
  EXPECT_EQ(fed.events[1], LineEvent::bad_byte);
  EXPECT_EQ(fed.events[2], LineEvent::bad_byte);  // an arrow key's escape sequence
  EXPECT_EQ(fed.events[3], LineEvent::line);
  std::string nul("a");
  nul.push_back('\0');
  nul += "\n";
  fed = feed(editor, nul);
  EXPECT_EQ(fed.events[0], LineEvent::bad_byte);
}

TEST(LineEditor, TabIsASpaceCtrlCCancelsBlankIsEmpty) {
  LineEditor editor;
  const Fed fed = feed(editor, "get\tc_l\nhalf\x03   \n");
  ASSERT_EQ(fed.events.size(), 3u);
  EXPECT_EQ(fed.lines[0], "get c_l");
  EXPECT_EQ(fed.events[1], LineEvent::cancelled);
  EXPECT_EQ(fed.events[2], LineEvent::empty);
}

TEST(LineEditor, ScriptedInputDoesNotLookLikeATerminal) {
  LineEditor editor;
  feed(editor, "get c_l\nset c_l 1\r\nparams\n");
  EXPECT_FALSE(editor.saw_terminal());
  // A bare CR is judged by the console, which knows the line (ROSArduinoBridge's client sends
  // "e\r"): the editor alone does not take it for a person.
  feed(editor, "e\rm 1 2\r");
  EXPECT_FALSE(editor.saw_terminal());
  feed(editor, "sta\x7f");  // a DEL is a person editing
  EXPECT_TRUE(editor.saw_terminal());
}

}  // namespace
}  // namespace odocal::console

// The maze text format: a hand-written maze read wall by wall, malformed texts refused with the
// line and column of the first wrong character, and the built-in practice maze.

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "odocal/sim/maze.hpp"
#include "odocal/sim/random.hpp"

namespace odocal::sim {
namespace {

// Row 2 (top): a wall between columns 0 and 1. Grid line 2: a wall under column 2. Row 1: a wall
// between columns 1 and 2. Grid line 1: a wall under column 0. Row 0: open.
constexpr std::string_view three_by_three =
    "+---+---+---+\n"
    "|   |       |\n"
    "+   +   +---+\n"
    "|       |   |\n"
    "+---+   +   +\n"
    "|           |\n"
    "+---+---+---+\n";

// The same maze with one line replaced (index from 0).
std::string with_line(std::size_t index, std::string_view replacement) {
  std::string out;
  std::size_t line = 0u;
  std::size_t start = 0u;
  while (start < three_by_three.size()) {
    const std::size_t end = three_by_three.find('\n', start);
    out += line == index ? replacement : three_by_three.substr(start, end - start);
    out += '\n';
    start = end + 1u;
    ++line;
  }
  return out;
}

MazeTextStatus parse_into_fresh(std::string_view text) {
  Maze maze;
  return parse_maze_text(text, maze);
}

TEST(MazeText, ReadsAHandWrittenThreeByThreeWallByWall) {
  Maze maze;
  const MazeTextStatus status = parse_maze_text(three_by_three, maze);
  ASSERT_TRUE(status.ok()) << to_string(status.error);
  ASSERT_EQ(maze.width(), 3u);
  ASSERT_EQ(maze.height(), 3u);
  Maze expected(3u, 3u);  // the perimeter
  expected.set_wall(0u, 2u, Side::east, true);
  expected.set_wall(2u, 2u, Side::south, true);
  expected.set_wall(1u, 1u, Side::east, true);
  expected.set_wall(0u, 1u, Side::south, true);
  EXPECT_EQ(maze, expected);
  // The shared walls, seen from both cells; an open side and the perimeter.
  EXPECT_TRUE(maze.has_wall(1u, 2u, Side::west));
  EXPECT_TRUE(maze.has_wall(2u, 1u, Side::north));
  EXPECT_TRUE(maze.has_wall(2u, 1u, Side::west));
  EXPECT_TRUE(maze.has_wall(0u, 0u, Side::north));
  EXPECT_FALSE(maze.has_wall(1u, 0u, Side::north));
  EXPECT_FALSE(maze.has_wall(0u, 2u, Side::south));
  for (std::uint32_t i = 0u; i < 3u; ++i) {
    EXPECT_TRUE(maze.has_wall(i, 0u, Side::south));
    EXPECT_TRUE(maze.has_wall(i, 2u, Side::north));
    EXPECT_TRUE(maze.has_wall(0u, i, Side::west));
    EXPECT_TRUE(maze.has_wall(2u, i, Side::east));
  }
}

TEST(MazeText, AcceptsCrLfTrailingBlankLinesRoundPostsAndLabels) {
  const std::string text =
      "o---o---o\r\n"
      "| S   G |\r\n"
      "o---o---o\r\n"
      "\r\n"
      "   \n";
  Maze maze;
  ASSERT_TRUE(parse_maze_text(text, maze).ok());
  EXPECT_EQ(maze, Maze(2u, 1u));
}

TEST(MazeText, RefusesAMixedWallSpanAtItsOddCharacter) {
  const MazeTextStatus status = parse_into_fresh(with_line(2u, "+   +- -+---+"));
  EXPECT_EQ(status.error, MazeTextError::span_expected);
  EXPECT_EQ(status.line, 3u);
  EXPECT_EQ(status.column, 7u);
}

TEST(MazeText, RefusesAForeignCharacterBetweenCells) {
  const MazeTextStatus status = parse_into_fresh(with_line(1u, "|   x       |"));
  EXPECT_EQ(status.error, MazeTextError::side_expected);
  EXPECT_EQ(status.line, 2u);
  EXPECT_EQ(status.column, 5u);
}

TEST(MazeText, RefusesAMissingPost) {
  const MazeTextStatus status = parse_into_fresh(with_line(4u, "+---+   -   +"));
  EXPECT_EQ(status.error, MazeTextError::post_expected);
  EXPECT_EQ(status.line, 5u);
  EXPECT_EQ(status.column, 9u);
}

TEST(MazeText, RefusesAWallCharacterInsideACell) {
  const MazeTextStatus status = parse_into_fresh(with_line(5u, "|     -     |"));
  EXPECT_EQ(status.error, MazeTextError::cell_expected);
  EXPECT_EQ(status.line, 6u);
  EXPECT_EQ(status.column, 7u);
}

TEST(MazeText, RefusesLinesOfAnotherLength) {
  MazeTextStatus status = parse_into_fresh(with_line(3u, "|       |"));
  EXPECT_EQ(status.error, MazeTextError::line_too_short);
  EXPECT_EQ(status.line, 4u);
  EXPECT_EQ(status.column, 10u);
  status = parse_into_fresh(with_line(3u, "|       |   |  "));
  EXPECT_EQ(status.error, MazeTextError::line_too_long);
  EXPECT_EQ(status.line, 4u);
  EXPECT_EQ(status.column, 14u);
  status = parse_into_fresh("+---+--\n|   |\n+---+\n");
  EXPECT_EQ(status.error, MazeTextError::line_too_short);
  EXPECT_EQ(status.line, 1u);
  EXPECT_EQ(status.column, 8u);
}

TEST(MazeText, RefusesATextEndingAfterARowOfCells) {
  // The south edge left blank: six lines, the last a row of cells.
  const MazeTextStatus status = parse_into_fresh(with_line(6u, ""));
  EXPECT_EQ(status.error, MazeTextError::no_last_posts);
  EXPECT_EQ(status.line, 7u);
  EXPECT_EQ(status.column, 1u);
}

TEST(MazeText, RefusesEmptyAndOversizedTexts) {
  EXPECT_EQ(parse_into_fresh("").error, MazeTextError::empty);
  EXPECT_EQ(parse_into_fresh("\n  \n").error, MazeTextError::empty);
  std::string wide = "+";
  for (std::uint32_t c = 0u; c < max_maze_cells + 1u; ++c) {
    wide += "---+";
  }
  const MazeTextStatus status = parse_into_fresh(wide + "\n");
  EXPECT_EQ(status.error, MazeTextError::too_large);
  EXPECT_EQ(status.line, 1u);
  EXPECT_EQ(status.column, max_maze_cells * 4u + 2u);
}

TEST(MazeText, LeavesTheMazeAsItWasOnError) {
  Maze maze(2u, 2u);
  maze.set_wall(0u, 0u, Side::east, true);
  const Maze before = maze;
  EXPECT_FALSE(parse_maze_text(with_line(3u, "|   x   |   |"), maze).ok());
  EXPECT_EQ(maze, before);
}

TEST(MazeText, DescribesAnErrorWithItsLineAndColumn) {
  char text[160];
  const MazeTextStatus status{MazeTextError::side_expected, 12u, 305u};
  const std::size_t length = describe(status, text, sizeof text);
  const std::string expected =
      std::string("line 12, column 305: ") + to_string(MazeTextError::side_expected);
  EXPECT_EQ(std::string(text), expected);
  EXPECT_EQ(length, expected.size());
  // Truncated, still terminated.
  char small[8];
  EXPECT_EQ(describe(status, small, sizeof small), 7u);
  EXPECT_EQ(std::string(small), "line 12");
}

// The text of `maze`, written by the test from the format's definition.
std::string text_of(const Maze& maze) {
  std::string text;
  for (std::uint32_t from_top = 0u; from_top <= maze.height(); ++from_top) {
    const std::uint32_t line = maze.height() - from_top;  // grid line, from the south
    text += '+';
    for (std::uint32_t c = 0u; c < maze.width(); ++c) {
      const bool wall = line < maze.height() ? maze.has_wall(c, line, Side::south)
                                             : maze.has_wall(c, line - 1u, Side::north);
      text += wall ? "---+" : "   +";
    }
    text += '\n';
    if (line == 0u) {
      break;
    }
    const std::uint32_t row = line - 1u;
    for (std::uint32_t c = 0u; c < maze.width(); ++c) {
      text += maze.has_wall(c, row, Side::west) ? "|   " : "    ";
    }
    text += maze.has_wall(maze.width() - 1u, row, Side::east) ? "|\n" : " \n";
  }
  return text;
}

TEST(MazeText, ReadsBackRandomMazesOfAnyRectangularSize) {
  Random random(16u);
  const std::uint32_t sizes[][2] = {{16u, 16u}, {5u, 9u}, {1u, 7u}, {32u, 2u}};
  for (const auto& size : sizes) {
    Maze maze(size[0], size[1]);
    for (std::uint32_t row = 0u; row < size[1]; ++row) {
      for (std::uint32_t c = 0u; c < size[0]; ++c) {
        maze.set_wall(c, row, Side::north, random.uniform() < 0.4);
        maze.set_wall(c, row, Side::east, random.uniform() < 0.4);
      }
    }
    Maze read;
    const MazeTextStatus status = parse_maze_text(text_of(maze), read);
    ASSERT_TRUE(status.ok()) << size[0] << "x" << size[1] << " " << to_string(status.error);
    EXPECT_EQ(read, maze) << size[0] << "x" << size[1];
  }
}

TEST(MazeText, PracticeMazeIsSixBySixWithAWestCorridor) {
  Maze read;
  ASSERT_TRUE(parse_maze_text(practice_maze_text(), read).ok());
  const Maze maze = practice_maze();
  EXPECT_EQ(maze, read);
  ASSERT_EQ(maze.width(), 6u);
  ASSERT_EQ(maze.height(), 6u);
  // The start cell: walls west, south and east, open ahead (north).
  EXPECT_TRUE(maze.has_wall(0u, 0u, Side::east));
  EXPECT_FALSE(maze.has_wall(0u, 0u, Side::north));
  // The corridor: walled on both sides from row 0 to row 4, opening east at the top.
  for (std::uint32_t row = 0u; row < 5u; ++row) {
    EXPECT_TRUE(maze.has_wall(0u, row, Side::west)) << row;
    EXPECT_TRUE(maze.has_wall(0u, row, Side::east)) << row;
    EXPECT_FALSE(maze.has_wall(0u, row, Side::north)) << row;
  }
  EXPECT_FALSE(maze.has_wall(0u, 5u, Side::east));
  // Open cells to turn in: the middle of the area has no wall at all.
  for (const Side side : {Side::north, Side::east, Side::south, Side::west}) {
    EXPECT_FALSE(maze.has_wall(2u, 2u, side));
  }
}

}  // namespace
}  // namespace odocal::sim

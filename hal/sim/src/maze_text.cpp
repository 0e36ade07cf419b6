// The maze text format: reading it, describing its errors, and the built-in practice maze.

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "odocal/sim/maze.hpp"

namespace odocal::sim {

namespace {

// Characters per cell in a line: one post or side, then the cell's (or span's) three.
constexpr std::size_t columns_per_cell = 4u;

bool is_post(char c) {
  return c == '+' || c == 'o';
}

// A cell's inside may hold a label but nothing that reads as a wall or a post.
bool is_cell_inside(char c) {
  return c >= ' ' && c <= '~' && c != '|' && c != '-' && c != '+';
}

// Up to `count` characters of `text` from `pos` (none when `pos` is past its end): substr without
// its out-of-range throw, which would link libstdc++'s abort path into the QEMU image.
std::string_view slice(std::string_view text, std::size_t pos, std::size_t count) {
  pos = pos < text.size() ? pos : text.size();
  const std::size_t left = text.size() - pos;
  return std::string_view(text.data() + pos, count < left ? count : left);
}

// The next line of `text` from `offset` without its '\n' and a trailing '\r'; moves `offset`
// past it.
std::string_view next_line(std::string_view text, std::size_t& offset) {
  const std::size_t end = text.find('\n', offset);
  std::string_view line =
      slice(text, offset, end == std::string_view::npos ? text.npos : end - offset);
  offset = end == std::string_view::npos ? text.size() : end + 1u;
  if (!line.empty() && line.back() == '\r') {
    line.remove_suffix(1u);
  }
  return line;
}

bool is_blank(std::string_view line) {
  for (const char c : line) {
    if (c != ' ' && c != '\t') {
      return false;
    }
  }
  return true;
}

// The text's lines up to its last non-blank one.
std::size_t count_lines(std::string_view text) {
  std::size_t offset = 0u;
  std::size_t lines = 0u;
  std::size_t last = 0u;
  while (offset < text.size()) {
    const std::string_view line = next_line(text, offset);
    ++lines;
    if (!is_blank(line)) {
      last = lines;
    }
  }
  return last;
}

MazeTextStatus fail(MazeTextError error, std::size_t line_index, std::size_t column_index) {
  return MazeTextStatus{error, static_cast<std::uint32_t>(line_index + 1u),
                        static_cast<std::uint32_t>(column_index + 1u)};
}

// Checks a line's length against the first line's (in characters).
MazeTextStatus check_length(std::string_view line, std::size_t length, std::size_t index) {
  if (line.size() < length) {
    return fail(MazeTextError::line_too_short, index, line.size());
  }
  if (line.size() > length) {
    return fail(MazeTextError::line_too_long, index, length);
  }
  return MazeTextStatus{};
}

// A row of posts: grid line `grid_line` (counted from the south). Sets the walls along it.
MazeTextStatus read_posts(std::string_view line, std::size_t index, std::uint32_t width,
                          std::uint32_t grid_line, Maze& maze) {
  for (std::uint32_t c = 0u; c <= width; ++c) {
    const std::size_t at = c * columns_per_cell;
    if (!is_post(line[at])) {
      return fail(MazeTextError::post_expected, index, at);
    }
    if (c == width) {
      break;
    }
    const std::string_view span = slice(line, at + 1u, 3u);
    const bool wall = span == "---";
    if (!wall && span != "   ") {
      const std::size_t odd = span.find_first_not_of(span[0] == '-' ? '-' : ' ');
      return fail(MazeTextError::span_expected, index, at + 1u + (odd == span.npos ? 0u : odd));
    }
    // The line below row r is grid line r: cell (c, r)'s south, cell (c, r − 1)'s north.
    if (grid_line < maze.height()) {
      maze.set_wall(c, grid_line, Side::south, wall);
    } else {
      maze.set_wall(c, grid_line - 1u, Side::north, wall);
    }
  }
  return MazeTextStatus{};
}

// A row of cells: row `row` (counted from the south). Sets the walls between its cells.
MazeTextStatus read_cells(std::string_view line, std::size_t index, std::uint32_t width,
                          std::uint32_t row, Maze& maze) {
  for (std::uint32_t c = 0u; c <= width; ++c) {
    const std::size_t at = c * columns_per_cell;
    if (line[at] != '|' && line[at] != ' ') {
      return fail(MazeTextError::side_expected, index, at);
    }
    const bool wall = line[at] == '|';
    if (c < width) {
      maze.set_wall(c, row, Side::west, wall);
      for (std::size_t k = 1u; k <= 3u; ++k) {
        if (!is_cell_inside(line[at + k])) {
          return fail(MazeTextError::cell_expected, index, at + k);
        }
      }
    } else {
      maze.set_wall(c - 1u, row, Side::east, wall);
    }
  }
  return MazeTextStatus{};
}

// The width, from the first line: a post, then (span, post) pairs.
MazeTextStatus first_line_width(std::string_view line, std::uint32_t& width) {
  if (line.empty() || !is_post(line[0])) {
    return fail(MazeTextError::post_expected, 0u, 0u);
  }
  const std::size_t cells = (line.size() - 1u) / columns_per_cell;
  if (cells > max_maze_cells) {
    return fail(MazeTextError::too_large, 0u, max_maze_cells * columns_per_cell + 1u);
  }
  if (cells == 0u || (line.size() - 1u) % columns_per_cell != 0u) {
    // The line stops inside a span: name the first missing character.
    return fail(MazeTextError::line_too_short, 0u, line.size());
  }
  width = static_cast<std::uint32_t>(cells);
  return MazeTextStatus{};
}

}  // namespace

MazeTextStatus parse_maze_text(std::string_view text, Maze& maze) {
  const std::size_t lines = count_lines(text);
  if (lines == 0u) {
    return MazeTextStatus{MazeTextError::empty, 0u, 0u};
  }
  std::size_t offset = 0u;
  const std::string_view first = next_line(text, offset);
  std::uint32_t width = 0u;
  if (const MazeTextStatus status = first_line_width(first, width); !status.ok()) {
    return status;
  }
  if ((lines - 1u) / 2u > max_maze_cells) {
    return fail(MazeTextError::too_large, 2u * max_maze_cells + 1u, 0u);
  }
  if (lines % 2u == 0u) {
    return fail(MazeTextError::no_last_posts, lines, 0u);
  }
  const auto height = static_cast<std::uint32_t>((lines - 1u) / 2u);
  if (height == 0u) {
    return fail(MazeTextError::no_last_posts, 1u, 0u);
  }
  Maze read(width, height);
  const std::size_t length = width * columns_per_cell + 1u;
  offset = 0u;
  for (std::size_t index = 0u; index < lines; ++index) {
    const std::string_view line = next_line(text, offset);
    MazeTextStatus status = check_length(line, length, index);
    if (status.ok()) {
      // Line 0 is the north edge, grid line `height`; odd lines are rows of cells.
      const auto from_top = static_cast<std::uint32_t>(index / 2u);
      status = index % 2u == 0u ? read_posts(line, index, width, height - from_top, read)
                                : read_cells(line, index, width, height - 1u - from_top, read);
    }
    if (!status.ok()) {
      return status;
    }
  }
  maze = read;
  return MazeTextStatus{};
}

const char* to_string(MazeTextError error) {
  switch (error) {
    case MazeTextError::none:
      return "no error";
    case MazeTextError::empty:
      return "the maze text is empty";
    case MazeTextError::post_expected:
      return "expected a post ('+' or 'o')";
    case MazeTextError::span_expected:
      return "expected '---' (a wall) or three spaces (no wall) between two posts";
    case MazeTextError::side_expected:
      return "expected '|' (a wall) or a space (no wall) between two cells";
    case MazeTextError::cell_expected:
      return "a cell holds spaces or a label, not a wall or post character";
    case MazeTextError::line_too_short:
      return "the line ends early (every line has the first line's length, 4 per cell + 1)";
    case MazeTextError::line_too_long:
      return "the line is longer than the first line";
    case MazeTextError::no_last_posts:
      return "expected a row of posts (the south edge) after the last row of cells";
    case MazeTextError::too_large:
      return "more than 32 cells on a side";
  }
  return "unknown error";
}

std::size_t describe(const MazeTextStatus& status, char* buffer, std::size_t size) {
  if (buffer == nullptr || size == 0u) {
    return 0u;
  }
  std::size_t length = 0u;
  const auto put = [&](char c) {
    if (length + 1u < size) {
      buffer[length++] = c;
    }
  };
  const auto put_text = [&](const char* s) {
    for (; *s != '\0'; ++s) {
      put(*s);
    }
  };
  const auto put_number = [&](std::uint32_t n) {
    char digits[10];
    std::size_t count = 0u;
    do {
      digits[count++] = static_cast<char>('0' + n % 10u);
      n /= 10u;
    } while (n != 0u);
    while (count > 0u) {
      put(digits[--count]);
    }
  };
  if (status.line != 0u) {
    put_text("line ");
    put_number(status.line);
    if (status.column != 0u) {
      put_text(", column ");
      put_number(status.column);
    }
    put_text(": ");
  }
  put_text(to_string(status.error));
  buffer[length] = '\0';
  return length;
}

std::string_view practice_maze_text() {
  // The west column is a corridor of six cells walled on its east side but at the top, where it
  // opens into the north corridor; beside it an open area of 5x5 cells with an L of walls.
  return "+---+---+---+---+---+---+\n"
         "|                       |\n"
         "+   +---+---+---+---+   +\n"
         "|   |                   |\n"
         "+   +   +   +   +   +   +\n"
         "|   |                   |\n"
         "+   +   +   +   +---+   +\n"
         "|   |               |   |\n"
         "+   +   +   +   +   +   +\n"
         "|   |                   |\n"
         "+   +   +   +   +   +   +\n"
         "| S |                   |\n"
         "+---+---+---+---+---+---+\n";
}

Maze practice_maze() {
  Maze maze(6u, 6u);
  // The text is the project's own and its test holds that it reads; a failure would leave the
  // empty 6x6 square.
  static_cast<void>(parse_maze_text(practice_maze_text(), maze));
  return maze;
}

}  // namespace odocal::sim

#pragma once
/// @file
/// A micromouse maze for the simulator: standard geometry (180 mm cells, 12 mm walls, a 12x12 mm
/// post at every corner), the walls as axis-aligned rectangles, the common ASCII text format, a
/// built-in practice maze, and a ray cast for the wall sensors.
///
/// Fixed-size, no heap, no exceptions, no I/O (like the plant, it may run inside the QEMU image).
///
/// Frame: origin at the centre of the south-west corner post, x east, y north, mm; headings in
/// rad counter-clockwise from +x. Cell (column, row) spans [column·180, (column+1)·180] x
/// [row·180, (row+1)·180] between the centre lines of its walls; row 0 is the south row (the
/// bottom line of the text).

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace odocal::sim {

/// Distance between the centre lines of two neighbouring walls, mm.
inline constexpr double cell_pitch_mm = 180.0;
/// Thickness of a wall and side of a (square) post, mm.
inline constexpr double wall_thickness_mm = 12.0;
/// Largest maze side, cells (the classic maze is 16x16, the half-size one 32x32).
inline constexpr std::uint32_t max_maze_cells = 32u;

/// A pose in the maze frame: position, mm; heading, rad counter-clockwise from east.
struct MazePose {
  double x_mm = 0.0;
  double y_mm = 0.0;
  double theta_rad = 0.0;
};

/// A side of a cell.
enum class Side : std::uint8_t { north, east, south, west };

/// What a ray met.
enum class SurfaceKind : std::uint8_t { none, wall, post };

/// The first face a ray meets.
struct RayHit {
  SurfaceKind kind = SurfaceKind::none;
  /// From the ray's origin to the face, mm (0 when the origin lies inside a wall or post; the
  /// search limit when nothing was met).
  double distance_mm = 0.0;
  /// Angle between the ray and the face's normal, rad in [0, π/2] (0: square on).
  double incidence_rad = 0.0;
  /// Names the wall or post in this maze, the same for every ray (per-surface properties).
  std::uint32_t surface = 0u;
};

/// The walls of a rectangular maze. Posts stand at every corner whether walls meet there or not.
class Maze {
 public:
  /// A 1x1 maze with its four perimeter walls.
  Maze() : Maze(1u, 1u) {}
  /// A `width` x `height` maze (each clamped to [1, max_maze_cells]) with its perimeter walls and
  /// no inner wall.
  Maze(std::uint32_t width, std::uint32_t height);

  [[nodiscard]] std::uint32_t width() const { return width_; }
  [[nodiscard]] std::uint32_t height() const { return height_; }

  /// Whether cell (column, row) has a wall on `side`; false outside the maze.
  [[nodiscard]] bool has_wall(std::uint32_t column, std::uint32_t row, Side side) const;
  /// Puts or removes the wall on `side` of cell (column, row) (the neighbour shares it). Does
  /// nothing outside the maze.
  void set_wall(std::uint32_t column, std::uint32_t row, Side side, bool present);

  /// The centre of cell (column, row) with `heading_rad`.
  [[nodiscard]] static MazePose cell_centre(std::uint32_t column, std::uint32_t row,
                                            double heading_rad = 0.0);

  /// The first wall or post face met by the ray from (x_mm, y_mm) along `heading_rad`, looking no
  /// further than `max_distance_mm`. Walks the cells the ray crosses and tests only the walls and
  /// posts on their borders.
  [[nodiscard]] RayHit cast(double x_mm, double y_mm, double heading_rad,
                            double max_distance_mm) const;

  friend bool operator==(const Maze&, const Maze&) = default;

 private:
  struct Candidate;
  void test_cell(std::int64_t column, std::int64_t row, const Candidate& ray, RayHit& best) const;
  RayHit cast_everything(const Candidate& ray, double max_distance_mm) const;

  std::uint32_t width_ = 1u;
  std::uint32_t height_ = 1u;
  /// Walls along the line y = line·pitch: bit c spans column c.
  std::array<std::uint64_t, max_maze_cells + 1u> horizontal_{};
  /// Walls along the line x = line·pitch in row r: bit `line` of vertical_[r].
  std::array<std::uint64_t, max_maze_cells> vertical_{};
};

/// What is wrong with a maze text (the first problem found).
enum class MazeTextError : std::uint8_t {
  none,
  empty,           ///< no line at all
  post_expected,   ///< a row of posts needs '+' (or 'o') every fourth column
  span_expected,   ///< between two posts: "---" (a wall) or three spaces (none)
  side_expected,   ///< between two cells: '|' (a wall) or a space (none)
  cell_expected,   ///< a cell's three characters hold a wall or post character
  line_too_short,  ///< a line ends before the first line's length
  line_too_long,   ///< a line goes on after the first line's length
  no_last_posts,   ///< the text ends after a row of cells, not a row of posts
  too_large,       ///< more than max_maze_cells cells on a side
};

/// Where a maze text is wrong: `line` and `column` count from 1 (0 when the error has no place).
struct MazeTextStatus {
  MazeTextError error = MazeTextError::none;
  std::uint32_t line = 0u;
  std::uint32_t column = 0u;
  [[nodiscard]] bool ok() const { return error == MazeTextError::none; }
};

/// Reads the common text format of micromouse mazes: rows of posts ('+' or 'o') joined by "---"
/// for a wall or three spaces for none, alternating with rows of cells where '|' or a space stands
/// between two cells and each cell holds three characters (spaces, or a label such as 'S' or
/// 'G'). The first line is the north edge; every line has the first one's length (a trailing
/// '\r' and blank lines at the end are ignored). Any rectangular size up to max_maze_cells.
/// On success `maze` holds the walls; on error it is left as it was.
[[nodiscard]] MazeTextStatus parse_maze_text(std::string_view text, Maze& maze);

/// A short description of an error ("expected '|' or a space between two cells", ...).
[[nodiscard]] const char* to_string(MazeTextError error);

/// "line L, column C: <description>" (or the description alone without a place), written into
/// `buffer` (always terminated, truncated to `size` − 1 characters). Returns the length written.
std::size_t describe(const MazeTextStatus& status, char* buffer, std::size_t size);

/// The built-in practice maze (6x6): a corridor along the whole west edge and another along the
/// north edge, around an open area with a few walls to square up against. Start: cell (0, 0)
/// facing north.
[[nodiscard]] Maze practice_maze();

/// The practice maze as text (the format parse_maze_text reads).
[[nodiscard]] std::string_view practice_maze_text();

}  // namespace odocal::sim

// (d) Wall edges under a diagonal sensor and the wheels' scale from them.

#include <cmath>
#include <stdexcept>
#include <string>

#include "odocal/host/walls.hpp"

namespace odocal::host::walls {

std::vector<WallEdge> find_wall_edges(const std::vector<RunSample>& samples, std::size_t sensor,
                                      double threshold_counts) {
  if (sensor >= sensor_count) {
    throw std::invalid_argument("find_wall_edges: no sensor " + std::to_string(sensor));
  }
  // Hysteresis: a wall is taken to begin once the reading passes the threshold by a fifth and to
  // end once it falls a fifth below, so that a dim reading near the threshold (the axis grazing a
  // post's end face) flickering with the noise gives one edge, not three. The edge is placed at
  // the last crossing of the threshold itself before the switch.
  const double high = 1.2 * threshold_counts;
  const double low = 0.8 * threshold_counts;
  std::vector<WallEdge> edges;
  if (samples.empty()) {
    return edges;
  }
  bool wall = samples.front().lit_counts[sensor] >= threshold_counts;
  double crossing = samples.front().travel_mm;
  for (std::size_t i = 1u; i < samples.size(); ++i) {
    const double before = samples[i - 1u].lit_counts[sensor];
    const double now = samples[i].lit_counts[sensor];
    if ((before >= threshold_counts) != (now >= threshold_counts)) {
      // The beam has no width worth modelling: the crossing lies between the two samples, and
      // the middle is the estimate with the least worst-case error.
      crossing = 0.5 * (samples[i - 1u].travel_mm + samples[i].travel_mm);
    }
    if ((wall && now < low) || (!wall && now >= high)) {
      edges.push_back(WallEdge{crossing, wall, sensor});
      wall = !wall;
    }
  }
  return edges;
}

double nearest_edge_face_mm(double predicted_mm, bool falling) {
  const double shift = edge_face_mm(0.0, falling);
  const double boundary = std::round((predicted_mm - shift) / sim::cell_pitch_mm);
  return edge_face_mm(boundary * sim::cell_pitch_mm, falling);
}

CorridorLine fit_corridor_line(const SensorSet& sensors, const std::vector<RunSample>& samples,
                               double half_width_mm) {
  CorridorLine out;
  // Twice: straight first, then with the heading the first line's slope gives.
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<double> travel;
    std::vector<double> offset;
    for (const RunSample& sample : samples) {
      const CorridorPose pose =
          observe_corridor(sensors, sample.lit_counts[left_diagonal],
                           sample.lit_counts[right_diagonal], out.heading_rad, half_width_mm);
      if (pose.valid) {
        travel.push_back(sample.travel_mm);
        offset.push_back(pose.offset_mm);
      }
    }
    if (travel.size() < 2u) {
      throw std::invalid_argument("fit_corridor_line: fewer than two samples see both walls");
    }
    // The same straight line as the wheels' scale: offset = start + slope · travel.
    const WheelScale line = fit_wheel_scale(travel, offset);
    out = CorridorLine{line.start_mm, line.scale, std::atan(line.scale), travel.size()};
  }
  return out;
}

double position_at_edge_mm(const sim::SensorMount& mount, double edge_face, bool falling,
                           double offset_mm, double heading_rad, double half_width_mm) {
  const double corner_line = falling ? half_width_mm : half_width_mm + sim::wall_thickness_mm;
  return edge_face - look_ahead_mm(mount, offset_mm, heading_rad, corner_line);
}

WheelScale fit_wheel_scale(const std::vector<double>& true_position_mm,
                           const std::vector<double>& travel_mm) {
  const std::size_t n = true_position_mm.size();
  if (n != travel_mm.size() || n < 2u) {
    throw std::invalid_argument("fit_wheel_scale: needs at least two edges, each with a travel");
  }
  double mean_p = 0.0;
  double mean_t = 0.0;
  for (std::size_t i = 0u; i < n; ++i) {
    mean_p += true_position_mm[i];
    mean_t += travel_mm[i];
  }
  mean_p /= static_cast<double>(n);
  mean_t /= static_cast<double>(n);
  double spp = 0.0;
  double spt = 0.0;
  for (std::size_t i = 0u; i < n; ++i) {
    spp += (true_position_mm[i] - mean_p) * (true_position_mm[i] - mean_p);
    spt += (true_position_mm[i] - mean_p) * (travel_mm[i] - mean_t);
  }
  if (!(spp > 1.0)) {
    throw std::invalid_argument("fit_wheel_scale: the edges stand at one place");
  }
  WheelScale out;
  out.scale = spt / spp;
  out.start_mm = mean_t - out.scale * mean_p;
  out.edges = n;
  if (n > 2u) {
    double sum = 0.0;
    for (std::size_t i = 0u; i < n; ++i) {
      const double r = travel_mm[i] - out.start_mm - out.scale * true_position_mm[i];
      sum += r * r;
    }
    out.residual_sd_mm = std::sqrt(sum / static_cast<double>(n - 2u));
  }
  return out;
}

}  // namespace odocal::host::walls

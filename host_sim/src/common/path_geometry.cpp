#include "odocal/host/path_geometry.hpp"

#include "odocal/drive/robot_model.hpp"

namespace odocal::host {

PathEnd path_end(const drive::Path& path) {
  // Each segment an exact arc of the one model (drive::model::advance_arc).
  drive::model::PoseOf<double> p;
  for (std::uint8_t i = 0; i < path.count; ++i) {
    drive::model::advance_arc(p, static_cast<double>(path.segments[i].distance_m),
                              static_cast<double>(path.segments[i].angle_rad));
  }
  return PathEnd{p.x, p.y, p.theta};
}

}  // namespace odocal::host

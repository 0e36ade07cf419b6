// The session's one model in force: the geometry the factors put in force, a fit's result as
// factors, and the one table of plausible results every procedure checks against.
#include "model_in_force.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace odocal::host::session {
namespace {

TEST(ModelInForce, GeometryIsTheCoreModelsForTheFactors) {
  Factors f;
  f.c_l = 0.998;
  f.c_r = 1.002;
  f.wheelbase_mm = 151.2;
  f.wheelbase_arc_mm = 152.4;
  f.f_lat = 1.004;
  f.f_lon = 0.997;
  const drive::model::Geometry<double> g = geometry_in_force(f, 60.0);
  const double s = (0.998 / (1.004 * 0.997) + 1.002 / 0.997) / 2.0;
  EXPECT_DOUBLE_EQ(g.left_diameter, 60.0 * 0.998 / (1.004 * 0.997));
  EXPECT_DOUBLE_EQ(g.right_diameter, 60.0 * 1.002 / 0.997);
  EXPECT_NEAR(g.wheelbase, 151.2 * s, 1e-12);
  EXPECT_NEAR(g.wheelbase_arc, 152.4 * s, 1e-12);
}

TEST(ModelInForce, AFitReplacesTheGeometryAndResetsTheMaddahiFactors) {
  const Factors f = factors_for_fit(drive::model::Geometry<double>{59.8, 60.3, 153.1, 0.0}, 60.0);
  EXPECT_DOUBLE_EQ(f.c_l, 59.8 / 60.0);
  EXPECT_DOUBLE_EQ(f.c_r, 60.3 / 60.0);
  EXPECT_EQ(f.wheelbase_mm, 153.1);
  EXPECT_EQ(f.wheelbase_arc_mm, 0.0);
  EXPECT_EQ(f.f_lat, 1.0);
  EXPECT_EQ(f.f_lon, 1.0);
  // Put in force, those factors give the fitted geometry back.
  const drive::model::Geometry<double> g = geometry_in_force(f, 60.0);
  EXPECT_NEAR(g.left_diameter, 59.8, 1e-12);
  EXPECT_NEAR(g.right_diameter, 60.3, 1e-12);
  EXPECT_EQ(g.wheelbase, 153.1);
}

TEST(ModelInForce, OneTableNamesTheFirstImplausibleFigure) {
  Factors ok;
  ok.wheelbase_mm = 150.0;
  EXPECT_EQ(implausible_factors(ok, 150.0), "");  // arc 0: one wheelbase, nothing to check
  const struct {
    const char* name;
    void (*change)(Factors&);
  } cases[] = {
      {"c_l", [](Factors& f) { f.c_l = 0.949; }},
      {"c_r", [](Factors& f) { f.c_r = 1.051; }},
      {"wheelbase_mm", [](Factors& f) { f.wheelbase_mm = 165.1; }},
      {"wheelbase_arc_mm", [](Factors& f) { f.wheelbase_arc_mm = 134.9; }},
      {"f_lat", [](Factors& f) { f.f_lat = 0.89; }},
      {"f_lon", [](Factors& f) { f.f_lon = 1.11; }},
  };
  for (const auto& c : cases) {
    Factors f = ok;
    c.change(f);
    const std::string refusal = implausible_factors(f, 150.0);
    EXPECT_EQ(refusal.rfind(std::string(c.name) + " = ", 0), 0u) << refusal;
    EXPECT_NE(refusal.find("plausible range"), std::string::npos) << refusal;
  }
  // The edges are inside (closed ranges), NaN is not.
  Factors edge = ok;
  edge.c_l = 0.95;
  edge.wheelbase_mm = 165.0;
  edge.f_lon = 1.1;
  EXPECT_EQ(implausible_factors(edge, 150.0), "");
  edge.f_lat = std::nan("");
  EXPECT_EQ(implausible_factors(edge, 150.0).rfind("f_lat = nan", 0), 0u);
}

}  // namespace
}  // namespace odocal::host::session

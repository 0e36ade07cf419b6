#include "odocal/params/param_table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "alloc_counter.hpp"

namespace odocal::params {
namespace {

TEST(ParamTable, HasEveryDesignParameterAndEveryDriveConfigField) {
  // DESIGN "Parameters" minimum set, plus the DriveConfig fields of its time (every parameter,
  // and its stored id, is in StoredIdsNeverChange).
  const char* names[] = {"c_l",
                         "c_r",
                         "wheelbase_mm",
                         "wheel_diameter_mm",
                         "f_lat",
                         "f_lon",
                         "counts_per_rev",
                         "control_hz",
                         "kp",
                         "ki",
                         "kff",
                         "max_wheel_radps",
                         "cmd_timeout_ms",
                         "v_max_mps",
                         "w_max_radps",
                         "accel_mps2",
                         "alpha_radps2",
                         "settle_ms",
                         "stall_ms",
                         "stall_duty",
                         "max_illegal",
                         "wheelbase_arc_mm",
                         "wiring_fix"};
  for (const char* name : names) {
    ParamId id{};
    EXPECT_TRUE(find_param(name, std::strlen(name), id)) << name;
    EXPECT_STREQ(param_info(id).name, name);
  }
  // Parameters added since are in StoredIdsNeverChange, which counts them all.
  EXPECT_LE(sizeof(names) / sizeof(names[0]), param_count);
}

TEST(ParamTable, StoredIdsNeverChange) {
  // The ids are written in stored records, and the one list (ODOCAL_DRIVE_PARAMETERS) numbers
  // them by position: a parameter inserted or moved there would renumber what robots have saved.
  // A new parameter appends a line here with the next id.
  const std::pair<const char*, int> stored[] = {{"wheel_diameter_mm", 0},
                                                {"wheelbase_mm", 1},
                                                {"counts_per_rev", 2},
                                                {"c_l", 3},
                                                {"c_r", 4},
                                                {"f_lat", 5},
                                                {"f_lon", 6},
                                                {"control_hz", 7},
                                                {"kp", 8},
                                                {"ki", 9},
                                                {"kff", 10},
                                                {"max_wheel_radps", 11},
                                                {"cmd_timeout_ms", 12},
                                                {"v_max_mps", 13},
                                                {"w_max_radps", 14},
                                                {"accel_mps2", 15},
                                                {"alpha_radps2", 16},
                                                {"settle_ms", 17},
                                                {"stall_ms", 18},
                                                {"stall_duty", 19},
                                                {"max_illegal", 20},
                                                {"wheelbase_arc_mm", 21},
                                                {"wiring_fix", 22}};
  for (const auto& [name, id] : stored) {
    ParamId found{};
    ASSERT_TRUE(find_param(name, std::strlen(name), found)) << name;
    EXPECT_EQ(static_cast<int>(found), id) << name;
  }
  EXPECT_EQ(param_count, sizeof(stored) / sizeof(stored[0]));
}

TEST(ParamTable, NamesAreExactAndCaseSensitive) {
  ParamId id{};
  EXPECT_FALSE(find_param("C_L", 3, id));
  EXPECT_FALSE(find_param("c_", 2, id));
  EXPECT_FALSE(find_param("c_lx", 4, id));
  EXPECT_FALSE(find_param("", 0, id));
  EXPECT_FALSE(find_param(nullptr, 3, id));
  // Length-delimited: a longer buffer whose first 3 bytes are a name matches that name.
  EXPECT_TRUE(find_param("c_l 1.0", 3, id));
  EXPECT_EQ(id, ParamId::c_l);
}

TEST(ParamTable, DefaultsAreTheDriveConfigInitialisers) {
  const drive::DriveConfig reference{};
  const drive::DriveConfig from_table = to_drive_config(default_params());
  EXPECT_EQ(from_table.c_l, reference.c_l);
  EXPECT_EQ(from_table.c_r, reference.c_r);
  EXPECT_EQ(from_table.wheelbase_mm, reference.wheelbase_mm);
  EXPECT_EQ(from_table.wheel_diameter_mm, reference.wheel_diameter_mm);
  EXPECT_EQ(from_table.f_lat, reference.f_lat);
  EXPECT_EQ(from_table.f_lon, reference.f_lon);
  EXPECT_EQ(from_table.counts_per_rev, reference.counts_per_rev);
  EXPECT_EQ(from_table.control_hz, reference.control_hz);
  EXPECT_EQ(from_table.kp, reference.kp);
  EXPECT_EQ(from_table.ki, reference.ki);
  EXPECT_EQ(from_table.kff, reference.kff);
  EXPECT_EQ(from_table.max_wheel_radps, reference.max_wheel_radps);
  EXPECT_EQ(from_table.cmd_timeout_ms, reference.cmd_timeout_ms);
  EXPECT_EQ(from_table.v_max_mps, reference.v_max_mps);
  EXPECT_EQ(from_table.w_max_radps, reference.w_max_radps);
  EXPECT_EQ(from_table.accel_mps2, reference.accel_mps2);
  EXPECT_EQ(from_table.alpha_radps2, reference.alpha_radps2);
  EXPECT_EQ(from_table.settle_ms, reference.settle_ms);
  EXPECT_EQ(from_table.stall_ms, reference.stall_ms);
  EXPECT_EQ(from_table.stall_duty, reference.stall_duty);
  EXPECT_EQ(from_table.max_illegal, reference.max_illegal);
  // DESIGN: calibration factors default to 1.
  EXPECT_EQ(default_value(ParamId::c_l), 1.0f);
  EXPECT_EQ(default_value(ParamId::f_lon), 1.0f);
}

TEST(ParamTable, DefaultsAreInRangeAndAcceptedByTheDrive) {
  const ParamSet defaults = default_params();
  EXPECT_TRUE(all_in_range(defaults));
  EXPECT_TRUE(drive::valid(to_drive_config(defaults)));
  EXPECT_EQ(defaults.wheel.method, FactorMethod::defaults);
}

TEST(ParamTable, RangesAreClosedAndRefuseNonFinite) {
  for (std::size_t i = 0; i < param_count; ++i) {
    const auto id = static_cast<ParamId>(i);
    const ParamInfo& info = param_info(id);
    SCOPED_TRACE(info.name);
    EXPECT_LT(info.min, info.max);
    EXPECT_TRUE(in_range(id, info.min));
    EXPECT_TRUE(in_range(id, info.max));
    EXPECT_FALSE(in_range(id, std::nextafter(info.min, -1.0e30f)));
    EXPECT_FALSE(in_range(id, std::nextafter(info.max, 1.0e30f)));
    EXPECT_FALSE(in_range(id, NAN));
    EXPECT_FALSE(in_range(id, INFINITY));
    EXPECT_FALSE(in_range(id, -INFINITY));
    EXPECT_NE(std::string(info.unit), "");
  }
  EXPECT_FALSE(in_range(ParamId::count, 1.0f));
}

TEST(ParamTable, EveryRangeEndIsAcceptedByTheDrive) {
  // A value `set` accepts must be one the drive accepts (apart from the cross-field rule
  // wheelbase > diameter / 4, avoided here by using the widest wheelbase).
  for (std::size_t i = 0; i < param_count; ++i) {
    const auto id = static_cast<ParamId>(i);
    for (float value : {param_info(id).min, param_info(id).max}) {
      ParamSet set = default_params();
      if (id != ParamId::wheelbase_mm) {
        set.set(ParamId::wheelbase_mm, param_info(ParamId::wheelbase_mm).max);
      } else {
        set.set(ParamId::wheel_diameter_mm, param_info(ParamId::wheel_diameter_mm).min);
      }
      set.set(id, value);
      EXPECT_TRUE(drive::valid(to_drive_config(set))) << param_info(id).name << "=" << value;
    }
  }
}

TEST(ParamTable, ArcWheelbaseIsZeroOrWithin20PercentOfTheWheelbase) {
  ParamSet set = default_params();  // wheelbase_mm 150
  EXPECT_EQ(set.get(ParamId::wheelbase_arc_mm), 0.0f);
  for (const float arc : {0.0f, 120.0f, 151.2f, 180.0f}) {
    set.set(ParamId::wheelbase_arc_mm, arc);
    EXPECT_TRUE(drive::valid(to_drive_config(set))) << arc;
  }
  for (const float arc : {119.9f, 180.1f, 10.0f}) {
    set.set(ParamId::wheelbase_arc_mm, arc);
    const drive::ConfigCheck check = drive::check(to_drive_config(set));
    EXPECT_EQ(check.error, drive::ConfigError::wheelbase_arc) << arc;
    EXPECT_STREQ(drive::to_string(check),
                 "wheelbase_arc_mm must be 0 or within 20% of wheelbase_mm");
  }
  EXPECT_FALSE(in_range(ParamId::wheelbase_arc_mm, -1.0f));
}

TEST(ParamTable, IntegerParameterRefusesFractions) {
  EXPECT_TRUE(param_info(ParamId::max_illegal).integer);
  EXPECT_TRUE(in_range(ParamId::max_illegal, 32.0f));
  EXPECT_FALSE(in_range(ParamId::max_illegal, 32.5f));
}

TEST(ParamTable, DriveConfigRoundTrip) {
  ParamSet set = default_params();
  set.set(ParamId::c_l, 0.99f);
  set.set(ParamId::c_r, 1.01f);
  set.set(ParamId::wheelbase_mm, 151.5f);
  set.set(ParamId::max_illegal, 100.0f);
  const drive::DriveConfig config = to_drive_config(set);
  EXPECT_EQ(config.c_l, 0.99f);
  EXPECT_EQ(config.c_r, 1.01f);
  EXPECT_EQ(config.wheelbase_mm, 151.5f);
  EXPECT_EQ(config.max_illegal, 100u);
  ParamSet back = default_params();
  from_drive_config(config, back);
  EXPECT_TRUE(same(set, back));
}

TEST(ParamTable, AllocatesNothing) {
  test::AllocationWatch watch;
  ParamSet set = default_params();
  ParamId id{};
  (void)find_param("kp", 2, id);
  set.set(id, 0.1f);
  (void)all_in_range(set);
  (void)to_drive_config(set);
  EXPECT_EQ(watch.allocations(), 0u);
}

}  // namespace
}  // namespace odocal::params

// Tests of assessment/metric_labels: every metric the assessment produces has a written label
// and unit in the one catalogue, zones read by their anatomy, unknown ids still read as words.
#include "assessment/metric_labels.hpp"

#include <gtest/gtest.h>

#include "assessment/metric_catalog.hpp"

namespace acdr {
namespace {

TEST(MetricLabels, EveryCatalogueMetricHasAWrittenLabel) {
  for (const std::string& name : known_metric_names()) {
    EXPECT_TRUE(has_written_label(name)) << name;
    EXPECT_EQ(metric_label(name).find('_'), std::string::npos) << name;
  }
  for (const MetricInfo& q : zone_metric_catalog()) {
    const std::string id = zone_metric_name("spinal_cord_pll", q.name);
    EXPECT_TRUE(has_written_label(id)) << id;
    EXPECT_EQ(metric_label(id).find('_'), std::string::npos) << id;
  }
}

TEST(MetricLabels, NamesAndUnits) {
  EXPECT_EQ(metric_label("peak_instrument_force_N"), "Peak instrument force (N)");
  EXPECT_EQ(metric_label("zone_dwell_s"), "Time near danger zones (s)");
  EXPECT_EQ(metric_label("never_events"), "Never-events");
  EXPECT_EQ(metric_label_parts("nucleus_removed_mm3").unit, "mm³");
  EXPECT_EQ(metric_label_parts("endplate_peak_stress_MPa").unit, "MPa");
  // Per-zone metrics read with the zone's name, generated zones by their anatomy.
  EXPECT_EQ(metric_label("zone.spinal_cord_pll.peak_force_N"),
            "Spinal cord / PLL: peak force near it (N)");
  EXPECT_EQ(metric_label("zone.vertebral_artery_left.dwell_s"),
            "Left vertebral artery: time near it (s)");
  EXPECT_EQ(metric_label("zone.my_zone.inside_s"), "My zone: time inside (s)");
  // An id outside the catalogue still reads as words with its unit.
  EXPECT_FALSE(has_written_label("artery_left_closest_mm"));
  EXPECT_EQ(metric_label("artery_left_closest_mm"), "Artery left closest (mm)");
}

TEST(MetricLabels, ZoneNames) {
  EXPECT_EQ(zone_display_name("spinal_cord_pll"), "spinal cord / PLL");
  EXPECT_EQ(zone_title("nerve_root_left"), "Left nerve root");
  EXPECT_EQ(zone_title("endplate_c5_upper"), "C5 upper endplate");
  EXPECT_EQ(zone_display_name("Danger zone 3"), "Danger zone 3");
}

}  // namespace
}  // namespace acdr

// Zone findings in words: the zone's human name, the time inside and the peak force.
#include "assessment/zone_findings.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

void set_zone(Metrics& m, const std::string& id, double dwell, double inside, double peak,
              double entries, double never_event, double closest) {
  m.set("zone." + id + ".peak_force_N", peak);
  m.set("zone." + id + ".impulse_Ns", 0.5 * peak * dwell);
  m.set("zone." + id + ".dwell_s", dwell);
  m.set("zone." + id + ".inside_s", inside);
  m.set("zone." + id + ".closest_mm", closest);
  m.set("zone." + id + ".warnings", dwell > 0 ? 1 : 0);
  m.set("zone." + id + ".entries", entries);
  m.set("zone." + id + ".over_limit_events", peak > 1.0 ? 2 : 0);
  m.set("zone." + id + ".never_event", never_event);
}

TEST(ZoneFindings, NameTheZoneTheTimeAndTheForce) {
  Metrics m;
  set_zone(m, "vertebral_artery_left", 0, 0, 0, 0, 0, 9.8);
  set_zone(m, "endplate_c5_upper", 0.4, 0, 0.2, 0, 0, 0.12);
  set_zone(m, "spinal_cord_pll", 2.0, 1.7, 1.4, 1, 1, -0.6);
  const std::vector<ZoneFinding> f = zone_findings(m);
  ASSERT_EQ(f.size(), 2u);  // the artery was never approached
  EXPECT_EQ(f[0].id, "spinal_cord_pll");  // entered first
  EXPECT_EQ(f[0].text,
            "entered the spinal cord / PLL zone for 1.7 s at up to 1.4 N (a never-event), "
            "above its force limit 2 times");
  EXPECT_TRUE(f[0].never_event);
  EXPECT_EQ(f[1].text, "came within 0.12 mm of the C5 upper endplate zone for 0.4 s at up to 0.2 N");
}

TEST(ZoneFindings, ScenarioNamesAreUsedAsWritten) {
  Metrics m;
  set_zone(m, "vertebral_artery_l", 0.3, 0.1, 0.35, 1, 1, -0.2);
  const std::vector<ZoneFinding> f = zone_findings(m, {"Vertebral artery (L)"});
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].label, "Vertebral artery (L)");
  EXPECT_EQ(f[0].text.rfind("entered the Vertebral artery (L) zone for 0.1 s at up to 0.35 N", 0), 0u)
      << f[0].text;
  EXPECT_EQ(zone_display_name("nerve_root_right"), "right nerve root");
  EXPECT_EQ(zone_display_name("Danger zone 3"), "Danger zone 3");
}

TEST(ZoneFindings, NothingNearNothingSaid) {
  Metrics m;
  set_zone(m, "spinal_cord_pll", 0, 0, 0, 0, 0, 2.4);
  EXPECT_TRUE(zone_findings(m).empty());
  EXPECT_TRUE(zone_findings(Metrics{}).empty());
}

}  // namespace
}  // namespace acdr

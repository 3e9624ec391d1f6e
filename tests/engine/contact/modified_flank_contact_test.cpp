// The stylus contact on flanks with design modifications (gears/flank_modifications.h), spur and
// helical, against the nested brute-force search of tests/support/p1_fixtures.h (no Newton, no
// certificate): steep circular tip and root reliefs, crowning, end reliefs and a helix slope,
// with and without a random field on top, planned points on the involute inside and outside the
// relieved zones. Every contact is kOk and within 1 nm of the search, with and without the
// flank's stage-1 bound (which must not change a result), and the design modification moves the
// reading by what it removes: on the nominal flank the reported deviation at a point inside a
// relief is the relief's value there times cos(beta_b), to second order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "engine/contact/contact.h"
#include "engine/contact/contact_certificate.h"
#include "tests/support/helical_fixtures.h"
#include "tests/support/p1_fixtures.h"

namespace gearmc {
namespace {

FlankExtent extent_of(const InvoluteGear& g) {
  return {g.form_roll_length_mm(), g.tip_roll_length_mm(), 0.0, g.face_width_mm()};
}

// Steep but realistic: 30 µm of tip relief over 2 mm of roll, 15 µm of root relief over 1 mm,
// 5 µm of profile crowning, 20 µm of end relief over 3 mm, 8 µm of helix crowning, -10 µm of
// helix slope.
FlankModifications steep_modifications() {
  FlankModifications m;
  m.tip_relief = {30.0, 2.0};
  m.root_relief = {15.0, 1.0};
  m.profile_crowning_um = 5.0;
  m.end_relief = {20.0, 3.0};
  m.helix_crowning_um = 8.0;
  m.helix_slope_um = -10.0;
  return m;
}

TEST(ModifiedFlankContact, AgreesWithBruteForceInAndOutOfTheReliefs) {
  std::mt19937_64 rng(11);  // fixed seed
  std::normal_distribution<double> coefficient(0.0, 2.0);
  int checked = 0;
  double worst = 0.0, worst_design = 0.0;
  for (const bool helical : {false, true}) {
    GearParameters p = helical ? testing_support::helical_gear_parameters()
                               : testing_support::p1_gear_parameters();
    p.modifications = steep_modifications();
    const InvoluteGear gear(p);
    ASSERT_EQ(validate_gear_parameters(p), "");
    const double Lf = gear.form_roll_length_mm(), La = gear.tip_roll_length_mm();
    const double b = gear.face_width_mm();
    for (const bool random_field : {false, true}) {
      FlankDeviation dev;
      if (random_field) {
        dev.offset_um = coefficient(rng);
        std::vector<double> pc(8), hc(6);
        for (double& c : pc) c = coefficient(rng);
        for (double& c : hc) c = coefficient(rng);
        dev.profile_form = CubicBSpline(Lf, La, pc);
        dev.helix_form = CubicBSpline(0.0, b, hc);
      }
      for (FlankSide side : {FlankSide::kLeft, FlankSide::kRight}) {
        const Eigen::Vector2d eccentricity =
            random_field ? Eigen::Vector2d(0.002, 0.001) : Eigen::Vector2d::Zero();
        const AnalyticFlank flank(gear, 3, side, dev, eccentricity);
        const FlankCurvatureBound bound = flank_curvature_bound(flank, 1.0, Lf, La);
        // Roll lengths across the root relief, the middle and the tip relief; z across both end
        // reliefs and the middle.
        for (const double L : {Lf + 0.2, Lf + 0.8, Lf + 1.2, 0.5 * (Lf + La), La - 2.5, La - 1.5,
                               La - 0.6, La - 0.2}) {
          for (const double z : {0.5, 2.5, 0.5 * b, b - 1.0}) {
            for (const double R : {0.5, 1.0}) {
              const FlankPoint fp = gear.flank_point(3, side, L, z);
              const ContactResult r =
                  solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z);
              ASSERT_EQ(r.status, ContactResult::Status::kOk) << helical << " " << L << " " << z;
              if (R == 1.0) {  // the flank's stage-1 bound changes nothing
                const ContactResult with_bound =
                    solve_contact(flank, extent_of(gear), fp.point, fp.normal, R, L, z,
                                  planned_base_angle(fp), &bound);
                ASSERT_EQ(with_bound.status, ContactResult::Status::kOk);
                EXPECT_LT((with_bound.contact - r.contact).norm(), 1e-9);
              }
              const testing_support::BruteForcePoints s =
                  testing_support::brute_force_contact_points(flank, fp.point, fp.normal, R, L, z);
              EXPECT_LT((s.contact - r.contact).norm(), 1e-6) << helical << " " << L << " " << z;
              EXPECT_LT((s.centre - r.centre).norm(), 1e-6);
              worst = std::max(worst, (s.contact - r.contact).norm());
              if (!random_field) {
                // The reading moves along n by the design's transverse value times cos(beta_b)
                // (the helicoid's normal has that component along n_t; 1 on a spur gear), plus
                // R(1/cos(theta) - 1) >= 0 for a surface tilted by theta (a sphere over a tilted
                // plane; the relief's own curvature changes that by nanometres). theta from the
                // design's steepest slopes within R of the point, per unit of arc: along the
                // profile dm/dL r_b / L (ds = L / r_b dL), across the face dm/dz.
                const DesignModification& design = *gear.design_modification();
                double slope_L = 0.0, slope_z = 0.0;
                for (int k = -20; k <= 20; ++k) {
                  double v, d1, d2;
                  const double Lk = L + R * k / 20.0;
                  design.profile.evaluate(Lk, &v, &d1, &d2);
                  slope_L = std::max(slope_L, std::abs(d1) * 0.5 * gear.base_diameter_mm() / Lk);
                  design.helix.evaluate(z + R * k / 20.0, &v, &d1, &d2);
                  slope_z = std::max(slope_z, std::abs(d1));
                }
                const double theta = std::atan(1e-3 * std::hypot(slope_L, slope_z));
                const double second_order = 1e3 * R * (1.0 / std::cos(theta) - 1.0);
                const double expected =
                    design.value_um(L, z) * std::cos(gear.base_helix_angle_rad());
                const double reading = 1e3 * ((r.centre - fp.point).dot(fp.normal) - R);
                worst_design = std::max(worst_design, std::abs(reading - expected));
                // On a helicoid the normal line leaves the transverse section (its axial
                // component sin(beta_b)): it meets the design m sin(beta_b) away in z and along
                // the profile, where m differs by that times its slopes.
                const double cross = 1e-3 * std::abs(design.value_um(L, z)) *
                                     std::sin(gear.base_helix_angle_rad()) * (slope_L + slope_z);
                EXPECT_GT(reading, expected - cross - 0.02) << helical << " " << L << " " << z;
                EXPECT_LT(reading, expected + 1.2 * second_order + cross + 0.02)
                    << helical << " " << L << " " << z << " theta " << theta;
              }
              ++checked;
            }
          }
        }
      }
    }
  }
  std::printf(
      "modified flanks: %d contacts, worst |C - C_brute| %.3g nm, reading - design %.3g µm\n",
      checked, 1e6 * worst, worst_design);
  EXPECT_EQ(checked, 2 * 2 * 2 * 8 * 4 * 2);
}

}  // namespace
}  // namespace gearmc

// Several profile and helix traces per flank (`evaluation.profile_sections`, `helix_sections`):
// on a spur gear whose real flanks carry the known deviation d(L, z) = 0.01 z (L − 10) µm (a
// profile slope growing with the height z, a helix slope growing with the roll length L), each
// trace's true F_α is |∂d/∂L| over L_α = 0.01 z_k (L_α length) and its F_β 0.01 |L_k − 10| (L_β
// length) — hand formulas at the traces' positions: the centres of equal parts of L_β (profile)
// and L_α (helix) for scans, the grid's sections / columns spread alike on the grid. Also: items
// per gear = flanks × traces; the middle trace alone gives pitch and the charts; sections beyond
// the grid refused with the key.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/input_error.h"
#include "engine/evaluation/parameter_evaluation.h"
#include "engine/run/monte_carlo.h"
#include "engine/scenario/scenario.h"

namespace gearmc {
namespace {

std::string scenario_text(const std::string& evaluation, int sections_across_face = 5) {
  return "name: sections\nseed: 3\n"
         "gear: {teeth: 20, module_mm: 3, pressure_angle_deg: 20, face_width_mm: 20}\n"
         "tolerances: {standard: iso_1328_1_2013, grade: 5}\n"
         "probing: {points_along_profile: 8, sections_across_face: " +
         std::to_string(sections_across_face) +
         ", margin_fraction: 0.05, teeth: [1, 6]}\n"
         "deviations: {random: false, normal_um: \"0.01*z*(L-10)\"}\n"
         "evaluation: " +
         evaluation + "\n";
}

RunResults run_one(const MonteCarloRun& mc) {
  RunOptions o;
  o.end_gear = 1;
  o.threads = 1;
  return mc.run(o);
}

const std::vector<ParameterValue>& items(const RunResults& r, GearParameter p, int side) {
  return r.parameters->values[static_cast<int>(p)][side];
}

TEST(TraceSections, EachScannedTraceHasItsOwnValueAtItsPosition) {
  const Scenario s =
      parse_scenario(scenario_text("{parameters: [F_alpha, F_beta, f_Halpha], profile_points: 40, "
                                   "helix_points: 40, profile_sections: 3, helix_sections: 2}"),
                     "sections.yaml");
  const MonteCarloRun mc(s);
  const ParameterEvaluator& e = *mc.parameter_evaluator();
  const RunResults r = run_one(mc);
  ASSERT_TRUE(r.parameters);
  const double La = e.profile_end_mm() - e.profile_start_mm();
  const double Lb = e.helix_end_mm() - e.helix_start_mm();
  // L_β of b 20 mm, m 3: min(5 % b, m) = 1 mm from each face.
  EXPECT_DOUBLE_EQ(e.helix_start_mm(), 1.0);
  for (int side = 0; side < 2; ++side) {
    const auto& fa = items(r, GearParameter::kFalpha, side);
    const auto& fb = items(r, GearParameter::kFbeta, side);
    ASSERT_EQ(fa.size(), 2u * 3u);  // 2 probed teeth × 3 traces
    ASSERT_EQ(fb.size(), 2u * 2u);
    for (int flank = 0; flank < 2; ++flank) {
      for (int k = 0; k < 3; ++k) {
        const double z = 1.0 + 18.0 * (k + 0.5) / 3;  // centres of thirds of L_β: 4, 10, 16
        const double hand = 0.01 * z * La;
        const ParameterValue& v = fa[static_cast<std::size_t>(flank * 3 + k)];
        EXPECT_NEAR(v.true_dense, hand, 1e-9 * hand + 1e-12) << "side " << side << " trace " << k;
        // The 0.5 mm stylus on flanks tilted by at most 0.2 µm/mm: δRcomp's second order.
        EXPECT_NEAR(v.measured, hand, 5e-3) << "side " << side << " trace " << k;
      }
      for (int k = 0; k < 2; ++k) {
        const double L = e.profile_start_mm() + La * (k + 0.5) / 2;  // centres of halves of L_α
        const double hand = 0.01 * std::abs(L - 10) * Lb;
        const ParameterValue& v = fb[static_cast<std::size_t>(flank * 2 + k)];
        EXPECT_NEAR(v.true_dense, hand, 1e-9 * hand + 1e-12) << "side " << side << " trace " << k;
        EXPECT_NEAR(v.measured, hand, 1e-3) << "side " << side << " trace " << k;
      }
    }
  }
  // The charts keep the middle traces only: one profile and one helix trace per flank.
  ASSERT_TRUE(r.parameters->chart_gear);
  EXPECT_EQ(r.parameters->chart.profile.size(), 4u);
  EXPECT_EQ(r.parameters->chart.helix.size(), 4u);
}

TEST(TraceSections, OnTheGridTheTracesAreItsSectionsSpreadOverTheFace) {
  // Grid of 5 sections across the face between 5 % margins: z = 1, 5.5, 10, 14.5, 19 mm.
  // Three traces take sections ⌊(k + ½) 5 / 3⌋ = 0, 2, 4: z = 1, 10, 19 mm. One trace is the
  // section nearest mid face (z 10), as without the key.
  const Scenario three =
      parse_scenario(scenario_text("{parameters: [F_alpha], profile_sections: 3}"), "s.yaml");
  const Scenario one = parse_scenario(scenario_text("{parameters: [F_alpha]}"), "s.yaml");
  const MonteCarloRun mc3(three), mc1(one);
  const RunResults r3 = run_one(mc3), r1 = run_one(mc1);
  const double La =
      mc3.parameter_evaluator()->profile_end_mm() - mc3.parameter_evaluator()->profile_start_mm();
  const double zs[3] = {1.0, 10.0, 19.0};
  const auto& fa3 = items(r3, GearParameter::kFalpha, 0);
  const auto& fa1 = items(r1, GearParameter::kFalpha, 0);
  ASSERT_EQ(fa3.size(), 6u);
  ASSERT_EQ(fa1.size(), 2u);
  for (int flank = 0; flank < 2; ++flank) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(fa3[static_cast<std::size_t>(flank * 3 + k)].true_dense, 0.01 * zs[k] * La, 1e-9);
    }
    // The middle trace is the single trace of the run without the key, to the bit.
    EXPECT_EQ(fa3[static_cast<std::size_t>(flank * 3 + 1)].measured,
              fa1[static_cast<std::size_t>(flank)].measured);
  }
}

TEST(TraceSections, MoreTracesThanTheGridHasOrWithAProgramAreRefused) {
  const auto error_of = [](const std::string& text) {
    try {
      parse_scenario(text, "s.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string grid =
      error_of(scenario_text("{parameters: [F_alpha], profile_sections: 4}", 3));
  EXPECT_NE(grid.find("s.yaml:"), std::string::npos) << grid;
  EXPECT_NE(grid.find("evaluation.profile_sections"), std::string::npos) << grid;
  EXPECT_NE(grid.find("at most the grid's 3 sections"), std::string::npos) << grid;
  const std::string columns = error_of(scenario_text("{parameters: [F_beta], helix_sections: 9}"));
  EXPECT_NE(columns.find("at most the grid's 8 columns"), std::string::npos) << columns;
  // With scans the grid does not limit them.
  EXPECT_EQ(error_of(scenario_text(
                "{parameters: [F_alpha], profile_points: 10, profile_sections: 4}", 3)),
            "no error");
  // With a user's program (`run --plan`): refused, tests/engine/readings/plan_program_test.cpp.
}

}  // namespace
}  // namespace gearmc

// Machines drawn for a CMM's own verification results (engine/machine/verification.h): the
// parameter layout round-trips, the length errors are linear in it (the premise of the Gaussian
// posterior), the posterior equals the information form computed independently here, and it is
// calibrated: over 400 hidden machines drawn from the prior, the posterior predictive of
// quantities the verification did not measure (the tip error at a gear point; the z axis's
// length, held out of the test) gives z-scores of mean 0 and variance 1 (seeds: hidden machines
// 0xC0DE, their test noise 0xBEEF; bounds at about 4 standard errors: |mean| ≤ 0.2, variance within
// [0.75, 1.3], a false alarm below 1e-3).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/random_stream.h"
#include "engine/machine/verification.h"

namespace gearmc {
namespace {

struct DataSheet {
  LengthMpe mpe = parse_length_mpe("1.8 + L/300");
  MachinePrior prior = prior_for(mpe, MachineLayout::kBridge, {700, 1000, 600});
  ProbePrior probe = probe_prior_for(1.7);
  LengthTestOptions test;
  DataSheet() { test.stylus_mm = Eigen::Vector3d(0, 0, -50); }
  // The 35 standard lengths as rows (errors to be filled).
  std::vector<VerificationRow> rows(double u_um) const {
    std::vector<VerificationRow> out;
    const auto positions = length_test_positions(prior.travel_mm);
    for (std::size_t p = 0; p < positions.size(); ++p) {
      for (double f : test.fractions) {
        out.push_back({static_cast<int>(p), f * positions[p].line_mm, 0.0, u_um});
      }
    }
    return out;
  }
};

TEST(Verification, ParametersRoundTripAndErrorsAreLinearInThem) {
  const DataSheet s;
  const int n = machine_parameter_count(s.prior, s.probe);
  EXPECT_EQ(n, 3 * 3 * 2 * 3 + 3 + 6);
  std::mt19937_64 g(5);
  std::normal_distribution<double> normal;
  Eigen::VectorXd t1(n), t2(n);
  for (int j = 0; j < n; ++j) t1[j] = normal(g), t2[j] = normal(g);
  // The error of θ₁ + 2θ₂ is E(θ₁) + 2E(θ₂) on every length.
  const Eigen::VectorXd t3 = t1 + 2.0 * t2;
  for (int p = 0; p < 7; ++p) {
    const double l = 300.0 + 50.0 * p;
    const auto e = [&](const Eigen::VectorXd& t) {
      return length_error_um(machine_of(s.prior, t), probe_of(s.prior, s.probe, t, 0.0), p, l,
                             s.test);
    };
    EXPECT_NEAR(e(t3), e(t1) + 2.0 * e(t2), 1e-9) << p;
  }
  // machine_of puts each coefficient where draw_machine's layout says (x's positioning order 1
  // first, the squareness after the 54 axis coefficients, the probe last).
  Eigen::VectorXd unit = Eigen::VectorXd::Zero(n);
  unit[0] = 1.0;
  EXPECT_EQ(machine_of(s.prior, unit).axes[0].translation_um[0][1], 1.0);
  unit.setZero();
  unit[54] = 2.0;
  EXPECT_EQ(machine_of(s.prior, unit).squareness_xy_urad, 2.0);
  unit.setZero();
  unit[57 + 2] = 0.5;  // c₃
  EXPECT_EQ(probe_of(s.prior, s.probe, unit, 0.1).cos_um[1], 0.5);
}

TEST(Verification, PosteriorEqualsTheInformationForm) {
  // Σ = (Aᵀ U⁻¹ A + S⁻¹)⁻¹, μ = Σ Aᵀ U⁻¹ y, A built here by finite differences of the errors
  // (another route than the library's unit columns and Woodbury's form).
  const DataSheet s;
  std::vector<VerificationRow> rows = s.rows(0.3);
  for (std::size_t i = 0; i < rows.size(); ++i)
    rows[i].error_um = 0.1 * std::sin(1.0 + static_cast<double>(i));
  const MachinePosterior post = verification_posterior(s.prior, s.probe, rows, s.test);
  const int n = machine_parameter_count(s.prior, s.probe);
  const Eigen::VectorXd sd = machine_prior_sd(s.prior, s.probe);
  Eigen::MatrixXd a(rows.size(), n);
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd plus = Eigen::VectorXd::Zero(n), minus = Eigen::VectorXd::Zero(n);
    plus[j] = 0.5;
    minus[j] = -0.5;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const auto e = [&](const Eigen::VectorXd& t) {
        return length_error_um(machine_of(s.prior, t), probe_of(s.prior, s.probe, t, 0.0),
                               rows[i].position, rows[i].length_mm, s.test);
      };
      a(static_cast<Eigen::Index>(i), j) = e(plus) - e(minus);
    }
  }
  Eigen::VectorXd y(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) y[static_cast<Eigen::Index>(i)] = rows[i].error_um;
  const double w = 1.0 / (0.3 * 0.3);
  Eigen::MatrixXd precision = w * a.transpose() * a;
  precision.diagonal() += sd.array().square().inverse().matrix();
  const Eigen::MatrixXd cov = precision.inverse();
  const Eigen::VectorXd mean = cov * (w * a.transpose() * y);
  EXPECT_LT((post.mean - mean).norm(), 1e-9 * (1.0 + mean.norm()));
  const Eigen::MatrixXd lib_cov = post.factor * post.factor.transpose();
  EXPECT_LT((lib_cov - cov).norm(), 1e-8 * cov.norm());
}

TEST(Verification, PosteriorIsCalibratedOnWhatTheTestDidNotMeasure) {
  const DataSheet s;
  const double u = 0.2;
  const Eigen::Vector3d point(70.0, 20.0, 30.0), stylus(0, 0, -50);
  double sum = 0.0, sum2 = 0.0, zsum = 0.0, zsum2 = 0.0;
  const int hidden = 400;
  for (int h = 0; h < hidden; ++h) {
    const KinematicMachine truth = draw_machine(s.prior, 0xC0DE, static_cast<std::uint64_t>(h));
    const CmmProbe probe = draw_probe(s.probe, 0xC0DE, static_cast<std::uint64_t>(h));
    TrialStream noise(0xBEEF, static_cast<std::uint64_t>(h), TrialPurpose::kMachineDraw);
    std::vector<VerificationRow> rows = s.rows(u);
    for (VerificationRow& r : rows) {
      r.error_um =
          length_error_um(truth, probe, r.position, r.length_mm, s.test) + u * noise.normal();
    }
    // The z axis's lengths held out: the test measured the other six positions.
    const VerificationRow held = rows.back();  // z, 85 % of its line
    rows.erase(std::remove_if(rows.begin(), rows.end(),
                              [](const VerificationRow& r) { return r.position == 6; }),
               rows.end());
    const MachinePosterior post = verification_posterior(s.prior, s.probe, rows, s.test);
    // The predictive laws are linear in θ: N(g·μ, g Σ gᵀ) with g the unit responses — of the
    // tip error's x at the gear point, and of the held-out z length's error.
    const int n = machine_parameter_count(s.prior, s.probe);
    Eigen::VectorXd g(n), gz(n);
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd unit = Eigen::VectorXd::Zero(n);
      unit[j] = 1.0;
      g[j] = machine_of(s.prior, unit).tip_error_um(point, stylus).x();
      gz[j] = length_error_um(machine_of(s.prior, unit), probe_of(s.prior, s.probe, unit, 0.0),
                              held.position, held.length_mm, s.test);
    }
    const double z = (truth.tip_error_um(point, stylus).x() - g.dot(post.mean)) /
                     (post.factor.transpose() * g).norm();
    sum += z;
    sum2 += z * z;
    const double zz =
        (length_error_um(truth, probe, held.position, held.length_mm, s.test) - gz.dot(post.mean)) /
        (post.factor.transpose() * gz).norm();
    zsum += zz;
    zsum2 += zz * zz;
  }
  const double mean_held = zsum / hidden;
  const double var_held = zsum2 / hidden - mean_held * mean_held;
  std::printf("held-out z length: mean %.3f, variance %.3f\n", mean_held, var_held);
  EXPECT_LT(std::abs(mean_held), 0.2) << mean_held;
  EXPECT_GT(var_held, 0.75) << var_held;
  EXPECT_LT(var_held, 1.3) << var_held;
  const double mean_z = sum / hidden;
  const double var_z = sum2 / hidden - mean_z * mean_z;
  std::printf("posterior predictive z over %d hidden machines: mean %.3f, variance %.3f\n", hidden,
              mean_z, var_z);
  EXPECT_LT(std::abs(mean_z), 0.2) << mean_z;
  EXPECT_GT(var_z, 0.75) << var_z;
  EXPECT_LT(var_z, 1.3) << var_z;
}

TEST(Verification, MachinesDrawnFromThePosteriorReproduceTheMeasuredErrors) {
  // One hidden machine's 35 errors measured with u = 0.05 µm: the kept machines' errors at those
  // lengths lie within a few u of the measured ones, and much nearer than the prior's spread.
  const DataSheet s;
  // A machine that passed its acceptance tests (the first kept of seed 7).
  const ConstrainedMachines one = draw_constrained(s.prior, s.mpe, 1, 1000, 7, s.test, s.probe);
  ASSERT_EQ(one.kept.size(), 1u);
  const KinematicMachine& truth = one.kept[0];
  const CmmProbe& probe = one.probes[0];
  std::vector<VerificationRow> rows = s.rows(0.05);
  for (VerificationRow& r : rows) {
    r.error_um = length_error_um(truth, probe, r.position, r.length_mm, s.test);
  }
  const MachinePosterior post = verification_posterior(s.prior, s.probe, rows, s.test);
  const ConstrainedMachines c =
      draw_constrained(s.prior, s.mpe, 20, 2000, 11, s.test, s.probe, 0.0, &post);
  ASSERT_FALSE(c.refused) << c.why;
  double worst = 0.0;
  for (std::size_t m = 0; m < c.kept.size(); ++m) {
    for (const VerificationRow& r : rows) {
      worst = std::max(
          worst, std::abs(length_error_um(c.kept[m], c.probes[m], r.position, r.length_mm, s.test) -
                          r.error_um));
    }
  }
  EXPECT_LT(worst, 0.25);  // 5 u; the prior's errors reach MPE_E, 2 … 4.6 µm
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_NEAR(post.predicted_um[i], rows[i].error_um, 0.1) << i;
    EXPECT_LT(post.predicted_sd_um[i], 0.05) << i;
  }
}

TEST(Verification, WithoutADataSheetTheTableSetsThePriorsScales) {
  // Tables of machines of two classes far apart — 0.6 + L/900 and 6 + L/90 µm, ten machines each,
  // kept by their MPE, measured with u = 0.1 µm — give prior scales whose MPE at 500 mm
  // separates the classes and lies within a factor 4 of each class's on the median (type-II
  // maximum likelihood from one table is a rough estimate: the test asks for the order of
  // magnitude, not the value).
  DataSheet s;
  for (const char* text : {"0.6 + L/900", "6 + L/90"}) {
    const LengthMpe truth = parse_length_mpe(text);
    MachinePrior prior = prior_for(truth, MachineLayout::kBridge, s.prior.travel_mm);
    const ConstrainedMachines kept = draw_constrained(prior, truth, 10, 2000, 17, s.test);
    ASSERT_FALSE(kept.refused) << kept.why;
    std::vector<double> ratio;
    for (std::size_t m = 0; m < kept.kept.size(); ++m) {
      TrialStream noise(0xBEEF, m, TrialPurpose::kMachineDraw);
      std::vector<VerificationRow> rows = s.rows(0.1);
      for (VerificationRow& r : rows) {
        r.error_um = length_error_um(kept.kept[m], CmmProbe{}, r.position, r.length_mm, s.test) +
                     0.1 * noise.normal();
      }
      const LengthMpe fitted = prior_scales_from_table(MachineLayout::kBridge, s.prior.travel_mm, 3,
                                                       ProbePrior{}, rows, s.test);
      ratio.push_back(fitted.at(500.0) / truth.at(500.0));
    }
    std::sort(ratio.begin(), ratio.end());
    const double median = 0.5 * (ratio[4] + ratio[5]);
    std::printf("%s: fitted MPE(500 mm) / true, median of 10: %.2f (%.2f … %.2f)\n", text, median,
                ratio.front(), ratio.back());
    EXPECT_GT(median, 0.25) << text;
    EXPECT_LT(median, 4.0) << text;
  }
}

}  // namespace
}  // namespace gearmc

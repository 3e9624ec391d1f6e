// Gross outliers among the readings (a dirty ball, a double trigger) found before the diagnosis,
// so that one bad reading cannot become a "noise" or "step_quantization" effect or hide a gap.
//
// The rule (a robust, local one: the model's structure varies smoothly along a profile scan, a
// gross outlier does not): along each profile scan (same gear, tooth, flank and face section j,
// points ordered by i) a reading's residual r_k is predicted from its neighbours, (r_{k−1} +
// r_{k+1})/2 inside the scan and 2 r_{k+1} − r_{k+2} (or its mirror) at an end; the prediction
// error e_k has variance 1.5 σ² inside and 6 σ² at an end for independent noise σ. σ is the
// robust scale of the residuals' second differences (prediction.h robust_noise_sigma: 1.4826
// MAD/√6, unaffected by a few outliers), at least the numerical floor. A reading is an outlier
// when |z_k| = |e_k| / (σ √1.5 or σ √6) exceeds z* = Φ⁻¹(1 − α/(2n)) with α = 1 % over the
// whole file of n readings (Bonferroni): with Gaussian noise and smooth structure the chance that
// any reading of a clean file is excluded is at most 1 %. The scan with the largest |z| loses the
// reading whose deletion leaves the smallest Σz² of the rest (an outlier spoils its neighbours'
// predictions too: at a scan's end its neighbour's |z| is as large as its own), and its
// predictions are made again without it, until no |z| exceeds z* (so an outlier's neighbours
// are not excluded with it). A reading at a scan's end is predicted by extrapolation, with twice
// the standard deviation of an inner one's prediction: there a gross error must be about twice
// as large to be found (≈ 11σ instead of ≈ 6σ for n = 2 400 readings). At most 5 % of the
// readings are excluded: more than that is not a few bad readings but a model or readings
// problem, and then none is excluded and the screen says so. Scans of fewer than 3 readings
// are not screened. Residuals in µm.
#pragma once

#include <string>
#include <vector>

#include "engine/apps/diagnose/prediction.h"

namespace gearmc {

struct ExcludedReading : PointKey {
  int row = 0;   // index into the residuals (= the readings' data rows)
  int line = 0;  // line in the readings file (0: readings made in memory)
  double residual_um = 0.0;
  double z_score = 0.0;  // the standardised prediction error when it was excluded
};

struct OutlierScreen {
  double family_false_alarm = 0.01;  // α over the whole file
  double threshold_z = 0.0;          // z*
  double sigma_um = 0.0;             // the scale σ used
  int screened = 0;                  // readings in scans of ≥ 3 readings
  std::vector<ExcludedReading> excluded;
  // Non-empty when more than kMaxOutlierFraction of the readings would be excluded: then none
  // is, and this says why.
  std::string not_applied;
};

inline constexpr double kMaxOutlierFraction = 0.05;

OutlierScreen screen_outliers(const Residuals& residuals, double family_false_alarm = 0.01);

// The residuals without the excluded readings (same order otherwise).
Residuals without_excluded(Residuals residuals, const OutlierScreen& screen);

}  // namespace gearmc

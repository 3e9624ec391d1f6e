// The coordinate-grid stage's part of the verdict (diagnosis_stages.h): a grid the readings'
// coordinates lie on (the scales' resolution, coordinate_grid.h) becomes the fitted effect
// scale_resolution, and a residual law the gap tests reject because of the latching is not left
// as unexplained structure when a simulation of the latched model reproduces it.
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

#include "engine/apps/diagnose/coordinate_grid.h"
#include "engine/apps/diagnose/diagnosis_stages.h"

namespace gearmc {
namespace {

// The coordinate grid as the fitted effect scale_resolution (its steps, read off the lattice).
FittedEffect scale_resolution_effect(const CoordinateGrid& grid) {
  FittedEffect e;
  e.name = "scale_resolution";
  e.absolute = true;
  const char* names[3] = {"x_um", "y_um", "z_um"};
  for (int a = 0; a < 3; ++a) {
    const CoordinateGridAxis& axis = grid.axes[static_cast<std::size_t>(a)];
    FittedValue v{names[a], "µm"};
    v.estimable = axis.observable && axis.step_um > 0.0;
    if (v.estimable) {
      v.value = axis.step_um;
      v.std_error = 0.0;  // read off the lattice, not estimated
    }
    e.coefficients.push_back(v);
  }
  e.parameters = e.coefficients;
  CandidateTest& t = e.evidence;
  t.name = e.name;
  t.candidate = -1;
  t.p_null = grid.false_alarm;
  t.effect_rms_um = grid.rms_um;
  t.significant = t.practical = t.accepted = true;
  t.note = "coordinate-grid stage: " + grid.note + "; p_null is the Rayleigh bound";
  e.fitted_rms_um = grid.rms_um;
  return e;
}

}  // namespace

namespace diagnosis_stages {

void coordinate_grid_verdict(const PreparedResiduals& prepared, Diagnosis& d) {
  CoordinateGrid& grid = d.coordinate_grid;
  // With a grid named or in the model: does the latched model explain the residuals' law (a
  // lumpy one the gap's KS test rejects, coordinate_grid.h)? Only when nothing else was found.
  const bool nothing_else = d.effects.empty() && !d.empirical.fitted;
  bool explained = false;
  // A grid found below the practical size (not named, not the model's) is checked too: its spread
  // is not in the noise floor, so the noise before latching is the floor itself.
  const bool below_practical = grid.found() && !grid.named && !grid.in_model;
  if (d.status == DiagnosisStatus::kTested && grid.found() &&
      (grid.named || grid.in_model ||
       (below_practical && nothing_else && d.finding == DiagnosisFinding::kUnexplained))) {
    std::array<double, 3> steps = {0.0, 0.0, 0.0};
    for (int a = 0; a < 3; ++a) {
      if (grid.axes[a].observable) steps[a] = grid.axes[a].step_um;
    }
    const double sigma_before = below_practical
                                    ? d.noise.sigma_um
                                    : std::sqrt(std::max(0.0, d.noise.sigma_um * d.noise.sigma_um -
                                                                  grid.rms_um * grid.rms_um));
    grid.check = latched_model_check(prepared.residuals.points, steps, sigma_before,
                                     d.noise.sigma_um, std::max(d.null_replicates, 199), d.seed);
    explained = nothing_else && grid.check.p >= d.alpha;
  }
  const auto leave_unexplained = [&](const std::string& why) {
    d.unexplained_structure = false;
    d.partially_explained_by.clear();
    d.unexplained_along = {};
    std::erase_if(d.notes,
                  [](const std::string& n) { return n.rfind("structure remains", 0) == 0; });
    std::ostringstream text;
    text << why << " (the residuals' KS distance " << grid.check.ks << " and RMS "
         << grid.check.rms_um
         << " µm are those of readings simulated with the latching, p = " << grid.check.p
         << " over " << grid.check.replicates << ")";
    d.notes.push_back(text.str());
  };
  if (d.status == DiagnosisStatus::kTested && grid.named) {
    d.effects.push_back(scale_resolution_effect(grid));
    d.effects.back().step = static_cast<int>(d.effects.size()) - 1;
    d.gap_detected = true;
    if (d.finding == DiagnosisFinding::kNone ||
        (d.finding == DiagnosisFinding::kUnexplained && explained)) {
      if (d.finding == DiagnosisFinding::kUnexplained) {
        leave_unexplained(
            "the residuals' shape that the gap tests reject is the latching's: with a step larger "
            "than the noise each point's error is set by its position");
      }
      d.name_effect("scale_resolution");
    }
    d.notes.push_back("scale resolution: " + grid.note + "; the noise floor includes its spread");
  } else if (d.status == DiagnosisStatus::kTested && grid.in_model &&
             d.finding == DiagnosisFinding::kUnexplained && explained) {
    leave_unexplained(
        "no gap: the residuals' shape that the gap tests reject is the latching's "
        "the model has");
    d.finding = DiagnosisFinding::kNone;
    d.gap_detected = false;
  } else if (d.status == DiagnosisStatus::kTested && below_practical &&
             d.finding == DiagnosisFinding::kUnexplained && explained) {
    leave_unexplained(
        "no gap: the residuals' spread that the gap tests reject is the rounding of the "
        "coordinates to their grid (" +
        grid.note + "), which the readings carry beside the model's noise");
    d.finding = DiagnosisFinding::kNone;
    d.gap_detected = false;
  } else if (grid.found()) {
    d.notes.push_back("coordinate grid: " + grid.note);
  }
}

}  // namespace diagnosis_stages
}  // namespace gearmc

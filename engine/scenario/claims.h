// Accuracy claims (`claims:` in a scenario): statements about a quantity of the Monte-Carlo run
// that `gearmc check` decides — e.g. "the per-flank maximum of δRcomp stays at most 4 µm at the
// 99.73 % quantile, at 95 % confidence". This is the typed, validated form; the reader
// (read_claims) turns every mistake into one InputError at file:line:column. Limits in µm.
#pragma once

#include <string>
#include <vector>

#include "core/input_error.h"

namespace gearmc {

class YamlValue;

// What a claim is about (per gear, from the run's per-gear outcome).
enum class ClaimQuantity {
  kDeltaRcompPoint,     // δRcomp of every valid point, µm
  kDeltaRcompFlankMax,  // the largest δRcomp of each flank, µm
  kTotalErrorPoint,     // |total point error| with the measurement effects, µm
  kParameterError,      // a gear parameter's measured − true (dense trace), µm, per item
};
enum class ClaimSide { kLeft, kRight, kBoth };
// kExpandedUncertainty: U = 2·√(E[v²]), the expanded uncertainty (k = 2) of a reading not
// corrected for the bias, 2·√(u² + b²) as the run's parameter tables print it (E[v²] = u² + b²,
// the gears weighted equally); only for a parameter error (`statistic: U`).
// kUOverT: U of a parameter error over its tolerance interval's width (2T for ±T, T for ≤ T), a
// ratio without unit; its limits are at_most / at_least.
enum class ClaimStatistic { kQuantile, kMean, kStd, kMax, kExpandedUncertainty, kUOverT };

struct ClaimSpec {
  std::string name;           // unique in the file
  std::string quantity_text;  // as written, e.g. "delta_rcomp.flank_max"
  ClaimQuantity quantity = ClaimQuantity::kDeltaRcompFlankMax;
  ClaimSide side = ClaimSide::kBoth;
  ClaimStatistic statistic = ClaimStatistic::kQuantile;
  double quantile = 0.5;  // p, for kQuantile (0 < p < 1)
  bool at_most = true;    // at_most_um (statistic ≤ limit) or at_least_um (statistic ≥ limit)
  double limit_um = 0.0;
  // Both at_least_um and at_most_um (mean, std, U only): lower_limit_um ≤ statistic ≤ limit_um,
  // with at_most = true; each confidence bound then one-sided at (1 + c)/2, so that the claim's
  // own error probability stays 1 − c.
  bool two_sided = false;
  double lower_limit_um = 0.0;
  double confidence = 0.95;  // 0 < c < 1
  InputLocation where;       // the claim's `name`
  // kParameterError: the ISO 1328-1 symbol (F_alpha, …, F_r) of `parameters.<symbol>.error`,
  // which the scenario's `evaluation:` must evaluate (checked by the scenario reader), and where
  // the quantity was written.
  std::string parameter;
  InputLocation quantity_where;
  InputLocation statistic_where;
  // kUOverT: the tolerance interval's width, µm (set by `check` from the scenario's tolerances).
  double tolerance_width_um = 0.0;
};

// " µm", or "" for a ratio (U/T): the unit of the statistic, its estimate, bounds and limits.
std::string claim_unit(const ClaimSpec& claim);

// The text of the statistic as written ("quantile 0.9973", "mean", "std", "max") and of the
// side ("left", "right", "both").
std::string statistic_text(const ClaimSpec& claim);
std::string side_text(ClaimSide side);
// The limit as stated: "≤ 4 µm", "≥ 1 µm" or "in [-0.5, 0.5] µm".
std::string limit_text(const ClaimSpec& claim);
// The one-sided error probability of each confidence bound: 1 − c, or (1 − c)/2 two-sided.
double bound_alpha(const ClaimSpec& claim);

// Reads the `claims:` list. `has_effects`: the scenario has at least one measurement effect
// (total_error.point needs them). Numbers outside their usual range append a located warning
// to `warnings` (when not null). Throws InputError.
std::vector<ClaimSpec> read_claims(const YamlValue& value, bool has_effects,
                                   std::vector<std::string>* warnings);

}  // namespace gearmc

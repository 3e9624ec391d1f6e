// One `gearmc uncertainty` evaluation put together — the GUM and the MCM results of every output
// and the §8 validation of JCGM 101:2008 — and its presentations: uncertainty.json, the terminal
// table and report.html. Units: those of each output (the model file does not name them).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/provenance.h"
#include "engine/apps/uncertainty/gum.h"
#include "engine/apps/uncertainty/mcm.h"
#include "engine/apps/uncertainty/model.h"
#include "engine/statistics/conformity.h"

namespace gearmc::uncertainty {

struct Evaluation {
  GumResult gum;
  McmResult mcm;
  // JCGM 101 §8 per output, against the MCM probabilistically symmetric interval (the verdict:
  // the GUM interval y ± U is probabilistically symmetric too) and against the shortest one
  // (shown too; for a symmetric output law its endpoints wander far more than the symmetric
  // ones, so it would fail an exact GUM by Monte-Carlo noise alone).
  std::vector<Validation> validation, validation_shortest;
  // JCGM 106:2012 per output with tolerance limits: the conformance probability p_c, the
  // probability that the measurand lies within [T_L, T_U] given the measurement — from the GUM
  // (Y ~ N(y, u²), JCGM 106 §7.6: p_c = Φ((T_U − y)/u) − Φ((T_L − y)/u)) and from the MCM (the
  // fraction of the M values within the limits).
  struct Conformity {
    bool set = false;
    double gum_probability = 0.0, mcm_probability = 0.0;
  };
  std::vector<Conformity> conformity;
  std::vector<std::string> warnings;
};

// JCGM 106 §7.6 conformance probability (engine/statistics/conformity.h, shared with the run's gear
// parameters).
using gearmc::conformance_probability;

// GUM + MCM + validation. `options` carries the MCM settings (seed, trials, threads, …).
Evaluation evaluate(const UncertaintyModel& model, const McmOptions& options);

// The contents of uncertainty.json (docs/formats.md). ν_eff = inf is written as null.
nlohmann::ordered_json evaluation_json(const UncertaintyModel& model, const McmOptions& options,
                                       const Evaluation& e, const Provenance& provenance);

// The terminal table: per output GUM against MCM (y, u, ν_eff, k, intervals) and the verdict.
void print_evaluation(std::ostream& out, const UncertaintyModel& model, const McmOptions& options,
                      const Evaluation& e);

// report.html: per output the MCM histogram with the GUM density over it and both intervals
// marked, the two CDFs, the budget |c_i| u(x_i) as bars, the adaptive stop block by block, the
// §8 verdict; then the model file.
std::string evaluation_report_html(const UncertaintyModel& model, const McmOptions& options,
                                   const Evaluation& e, const Provenance& provenance);

// Digits after the decimal point that show u with ndig + 2 significant digits (at least 0).
int display_decimals(double u, int ndig);

}  // namespace gearmc::uncertainty

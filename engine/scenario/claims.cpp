// The reader of `claims:` (see claims.h). Its keys, choices and defaults come from the scenario
// key table (engine/schema/scenario_keys.cpp), its number ranges from the `claims` range table
// (engine/schema/parameter_ranges.cpp).
#include "engine/scenario/claims.h"

#include <cstdio>
#include <map>

#include "core/yaml_reader.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

namespace gearmc {
namespace {

constexpr const char* kQuantities = "delta_rcomp.point, delta_rcomp.flank_max or total_error.point";

ClaimQuantity read_quantity(const YamlValue& value, bool has_effects) {
  const std::string text = value.as_string();
  if (text.rfind("parameters.", 0) == 0) {
    // A gear parameter's error, parameters.<symbol>.error: the symbol is checked against the
    // scenario's `evaluation:` once both are read (parse_scenario).
    const std::string rest = text.substr(11);
    const auto dot = rest.rfind('.');
    if (dot == std::string::npos || dot == 0 || rest.substr(dot) != ".error") {
      throw value.error(std::string(kQuantities) +
                        " or parameters.<symbol>.error (e.g. parameters.F_alpha.error)");
    }
    return ClaimQuantity::kParameterError;
  }
  if (text == "delta_rcomp.point") return ClaimQuantity::kDeltaRcompPoint;
  if (text == "delta_rcomp.flank_max") return ClaimQuantity::kDeltaRcompFlankMax;
  if (text == "total_error.point") {
    if (!has_effects) {
      throw value.error(
          "a quantity the run computes: total_error.point is the point error with the "
          "measurement effects, and this scenario has no `effects:` (use delta_rcomp.point, or "
          "add effects)");
    }
    return ClaimQuantity::kTotalErrorPoint;
  }
  throw value.error(kQuantities, did_you_mean(text, {"delta_rcomp.point", "delta_rcomp.flank_max",
                                                     "total_error.point"}));
}

void read_statistic(const YamlValue& value, ClaimSpec& claim, InputWarnings* warnings) {
  claim.statistic_where = value.location();
  const std::string expected =
      "mean, std, max, U, U_over_T or {quantile: p} with 1e-9 <= p <= 1 - 1e-9";
  if (value.is_map()) {
    const YamlMap map = value.as_map(child_keys("claims.statistic"));
    const YamlValue p =
        map.require("quantile", "the quantile p, 1e-9 <= p <= 1 - 1e-9 (e.g. 0.9973)");
    claim.statistic = ClaimStatistic::kQuantile;
    claim.quantile = read_ranged(p, claim_ranges().at("claims.statistic.quantile"), warnings);
    return;
  }
  if (!value.is_scalar() || value.is_quoted()) throw value.error(expected);
  const std::string word = value.as_string();
  const std::vector<std::string>& allowed = key_choices("claims.statistic");
  if (word == "quantile") throw value.error(expected + " (the quantile needs its p)");
  bool known = false;
  for (const std::string& a : allowed) known = known || a == word;
  if (!known) throw value.error(expected, did_you_mean(word, allowed));
  if ((word == "U" || word == "U_over_T") && claim.quantity != ClaimQuantity::kParameterError) {
    throw value.error(
        "a statistic of this quantity: " + word +
        " (U, the expanded uncertainty 2·√(u² + bias²), and U/T) is a statistic of a parameter "
        "error (quantity parameters.<symbol>.error)");
  }
  claim.statistic = word == "mean"       ? ClaimStatistic::kMean
                    : word == "std"      ? ClaimStatistic::kStd
                    : word == "U"        ? ClaimStatistic::kExpandedUncertainty
                    : word == "U_over_T" ? ClaimStatistic::kUOverT
                                         : ClaimStatistic::kMax;
}

}  // namespace

std::string side_text(ClaimSide side) {
  return side == ClaimSide::kLeft ? "left" : side == ClaimSide::kRight ? "right" : "both";
}

std::string claim_unit(const ClaimSpec& claim) {
  return claim.statistic == ClaimStatistic::kUOverT ? "" : " µm";
}

std::string limit_text(const ClaimSpec& claim) {
  char text[96];
  if (claim.two_sided) {
    std::snprintf(text, sizeof text, "in [%.10g, %.10g]", claim.lower_limit_um, claim.limit_um);
  } else {
    std::snprintf(text, sizeof text, "%s %.10g", claim.at_most ? "≤" : "≥", claim.limit_um);
  }
  return text + claim_unit(claim);
}

double bound_alpha(const ClaimSpec& claim) {
  return claim.two_sided ? 0.5 * (1.0 - claim.confidence) : 1.0 - claim.confidence;
}

std::string statistic_text(const ClaimSpec& claim) {
  switch (claim.statistic) {
    case ClaimStatistic::kQuantile: {
      char text[48];
      std::snprintf(text, sizeof text, "quantile %.10g", claim.quantile);
      return text;
    }
    case ClaimStatistic::kMean:
      return "mean";
    case ClaimStatistic::kStd:
      return "std";
    case ClaimStatistic::kMax:
      return "max";
    case ClaimStatistic::kExpandedUncertainty:
      return "U (k = 2)";
    case ClaimStatistic::kUOverT:
      return "U/T";
  }
  return "";
}

// claims: a list of {name (required, unique), quantity (required), side (left | right | both,
// default both), statistic (required: mean | std | max | U | U_over_T | {quantile: p}),
// at_most_um and/or at_least_um (both: a two-sided claim, for mean, std and U; U_over_T takes
// at_most / at_least, without unit), confidence (1e-9 <= c <= 1 - 1e-9, default 0.95)}.
std::vector<ClaimSpec> read_claims(const YamlValue& value, bool has_effects,
                                   std::vector<std::string>* warnings) {
  const std::string expected =
      "a list of claims, e.g. [{name: p1_4um, quantity: delta_rcomp.flank_max, statistic: "
      "{quantile: 0.9973}, at_most_um: 4.0, confidence: 0.95}]";
  if (!value.is_sequence()) throw value.error(expected);
  std::vector<ClaimSpec> claims;
  std::map<std::string, int> lines;  // name → line of its first use
  for (const YamlValue& item : value.as_sequence()) {
    if (!item.is_map()) throw item.error(expected);
    const YamlMap entry = item.as_map(child_keys("claims"));
    ClaimSpec claim;
    const YamlValue name = entry.require("name", "a name for the claim (unique in the file)");
    claim.name = name.as_string();
    claim.where = name.location();
    if (claim.name.empty() || claim.name.find_first_of("\n\r\t") != std::string::npos) {
      throw name.error("a non-empty name on one line");
    }
    if (const auto first = lines.find(claim.name); first != lines.end()) {
      throw name.error("a name not used before (claim '" + claim.name +
                       "' is already given at line " + std::to_string(first->second) + ")");
    }
    lines[claim.name] = name.location().line;
    const YamlValue quantity = entry.require("quantity", kQuantities);
    claim.quantity_text = quantity.as_string();
    claim.quantity = read_quantity(quantity, has_effects);
    claim.quantity_where = quantity.location();
    if (claim.quantity == ClaimQuantity::kParameterError) {
      claim.parameter = claim.quantity_text.substr(11, claim.quantity_text.size() - 11 - 6);
    }
    const std::string side = entry.get_choice("side", key_choices("claims.side"))
                                 .value_or(choice_default("claims.side"));
    claim.side = side == "left"    ? ClaimSide::kLeft
                 : side == "right" ? ClaimSide::kRight
                                   : ClaimSide::kBoth;
    read_statistic(entry.require("statistic", "mean, std, max, U, U_over_T or {quantile: p}"),
                   claim, warnings);
    // A ratio (U/T) has limits without unit; every other statistic's are in µm.
    const bool ratio = claim.statistic == ClaimStatistic::kUOverT;
    const std::string most = ratio ? "at_most" : "at_most_um";
    const std::string least = ratio ? "at_least" : "at_least_um";
    for (const char* other : {"at_most", "at_least", "at_most_um", "at_least_um"}) {
      if (other == most || other == least) continue;
      if (const auto wrong = entry.find(other)) {
        throw wrong->error(ratio ? "at_most / at_least for U_over_T (a ratio without unit, e.g. "
                                   "at_most: 0.15)"
                                 : "at_most_um / at_least_um (at_most and at_least, without unit, "
                                   "are the limits of statistic U_over_T)");
      }
    }
    const auto at_most = entry.find(most);
    const auto at_least = entry.find(least);
    const bool moment = claim.statistic == ClaimStatistic::kMean ||
                        claim.statistic == ClaimStatistic::kStd ||
                        claim.statistic == ClaimStatistic::kExpandedUncertainty || ratio;
    if (at_most && at_least && !moment) {
      throw at_least->error(
          "either at_most_um or at_least_um: both (a two-sided claim) are for mean, std and U; "
          "a quantile's two tails are two claims (e.g. quantile 0.025 at_least_um and quantile "
          "0.975 at_most_um), and a max has one limit");
    }
    if (!at_most && !at_least) {
      throw entry.missing(most, ratio ? "the claim's limit: at_most or at_least (a ratio)"
                                      : "the claim's limit: at_most_um or at_least_um (µm)");
    }
    claim.at_most = at_most.has_value();
    claim.limit_um = read_ranged(at_most ? *at_most : *at_least,
                                 claim_ranges().at("claims." + (at_most ? most : least)), warnings);
    if (at_most && at_least) {
      claim.two_sided = true;
      claim.lower_limit_um = read_ranged(*at_least, claim_ranges().at("claims." + least), warnings);
      if (!(claim.lower_limit_um < claim.limit_um)) {
        throw at_least->error("a lower limit below " + most + " (" + at_most->as_string() +
                              "): the claim is " + least + " ≤ statistic ≤ " + most);
      }
    }
    claim.confidence = number_default("claims.confidence");
    if (const auto c = entry.find("confidence")) {
      claim.confidence = read_ranged(*c, claim_ranges().at("claims.confidence"), warnings);
    }
    claims.push_back(std::move(claim));
  }
  return claims;
}

}  // namespace gearmc

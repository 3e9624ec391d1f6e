// report.html, the verdict and the terminal summary of `gearmc diagnose` (see
// diagnosis_report.h).
#include "engine/diagnose/diagnosis_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <sstream>

#include "engine/diagnose/report_plot_data.h"
#include "engine/report/html_report.h"
#include "engine/report/svg_plot.h"
#include "engine/stats/histogram.h"
#include "gears/involute_gear.h"

namespace gearmc {
namespace {

constexpr double kPi = std::numbers::pi;
// Okabe-Ito colours, the same meaning in every plot.
const char* const kRawColour = "#c8c8c8";
const char* const kBefore = "#D55E00";      // vermillion
const char* const kAfter = "#0072B2";       // blue
const char* const kFitted = "#009E73";      // bluish green
const char* const kNullBefore = "#E69F00";  // orange
const char* const kNullAfter = "#56B4E9";   // sky blue
// The most marks of one scatter series (report.html stays small at 10⁶ readings).
constexpr std::size_t kMaxScatterMarks = 5000;

std::string fixed(double v, int decimals = 3) {
  if (!std::isfinite(v)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string s = buffer;
  if (s.find_first_not_of("-0.") == std::string::npos) s = s.substr(s[0] == '-' ? 1 : 0);
  return s;
}

// A value with its standard error at a precision that follows the error (2 significant digits
// of the error, at most 4 decimals, at least 1).
std::string with_error(double value, double error) {
  if (!std::isfinite(value)) return "–";
  int decimals = 3;
  if (std::isfinite(error) && error > 0.0) {
    decimals = std::clamp(1 - static_cast<int>(std::floor(std::log10(error))), 1, 4);
  }
  std::string s = fixed(value, decimals);
  if (std::isfinite(error)) s += " ± " + fixed(error, decimals);
  return s;
}

std::string general(double v) {
  if (!std::isfinite(v)) return "–";
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

// A null-calibrated p-value: the smallest possible value 1/(K + 1) is shown as "p ≤ …".
std::string p_text(double p, int replicates) {
  if (!std::isfinite(p)) return "p –";
  if (replicates > 0 && p <= 1.0 / (replicates + 1) + 1e-12) {
    std::ostringstream bound;
    bound.precision(1);
    bound << 1.0 / (replicates + 1);
    return "p ≤ " + bound.str();
  }
  if (p < 1e-4) return "p < 0.0001";
  return "p = " + general(p);
}

bool is_library_effect(const std::string& name) {
  return name != "none" && name != "unexplained" && name != "not_tested";
}

// Parameters worth stating: |value| > 3 standard errors (a phase goes with its amplitude).
std::vector<const FittedValue*> significant_parameters(const FittedEffect& e) {
  std::vector<const FittedValue*> out;
  for (const FittedValue& v : e.parameters) {
    if (!v.estimable || !std::isfinite(v.value)) continue;
    if (v.name.rfind("phase_", 0) == 0) {
      const std::string order = v.name.substr(6, v.name.size() - 6 - 4);  // phase_<k>_deg
      const bool amplitude_shown = std::any_of(out.begin(), out.end(), [&](const FittedValue* a) {
        return a->name == "amplitude_" + order + "_um";
      });
      if (amplitude_shown) out.push_back(&v);
      continue;
    }
    if (std::abs(v.value) > 3.0 * v.std_error) out.push_back(&v);
  }
  if (out.empty()) {
    for (const FittedValue& v : e.parameters) {
      if (v.estimable && std::isfinite(v.value)) out.push_back(&v);
    }
  }
  return out;
}

std::string parameter_list(const FittedEffect& e, const char* separator) {
  std::string s;
  for (const FittedValue* v : significant_parameters(e)) {
    if (!s.empty()) s += separator;
    s += v->name + " = " + with_error(v->value, v->std_error) + " " + v->unit;
  }
  return s;
}

// Residual bin means along one axis: key → (mean x, mean before, mean after, count).
struct Bins {
  std::vector<double> x, before, after;
  std::vector<int> count;
};

Bins binned(const std::vector<long>& key, const std::vector<double>& x,
            const std::vector<double>& before, const std::vector<double>& after) {
  struct Sum {
    double x = 0, b = 0, a = 0;
    int n = 0;
  };
  std::map<long, Sum> sums;
  for (std::size_t k = 0; k < key.size(); ++k) {
    Sum& s = sums[key[k]];
    s.x += x[k];
    s.b += before[k];
    s.a += after[k];
    ++s.n;
  }
  Bins out;
  for (const auto& [unused, s] : sums) {
    out.x.push_back(s.x / s.n);
    out.before.push_back(s.b / s.n);
    out.after.push_back(s.a / s.n);
    out.count.push_back(s.n);
  }
  return out;
}

// How much the bin means vary beyond noise: RMS of (mean − overall mean) weighted by count, and
// the same expected from noise σ alone (σ √((B − 1)/n)), and their χ² ratio
// Σ n_b (m_b − m̄)² / ((B − 1) σ²).
struct AxisStructure {
  std::string axis;  // e.g. "approach azimuth"
  double rms_um = 0.0, noise_rms_um = 0.0, ratio = 0.0;
};

AxisStructure axis_structure(const std::string& axis, const Bins& b, double sigma) {
  AxisStructure s;
  s.axis = axis;
  const int bins = static_cast<int>(b.count.size());
  double n = 0.0, total = 0.0;
  for (int k = 0; k < bins; ++k) {
    n += b.count[k];
    total += b.count[k] * b.before[k];
  }
  if (bins < 2 || n <= 0.0 || sigma <= 0.0) return s;
  const double mean = total / n;
  double ss = 0.0;
  for (int k = 0; k < bins; ++k) ss += b.count[k] * (b.before[k] - mean) * (b.before[k] - mean);
  s.rms_um = std::sqrt(ss / n);
  s.noise_rms_um = sigma * std::sqrt((bins - 1) / n);
  s.ratio = ss / ((bins - 1) * sigma * sigma);
  return s;
}

// Everything the verdict, the summary and the plots share.
struct ReportData {
  int n = 0;
  double sigma = 0.0;
  std::vector<double> before, after, fitted_part;
  std::vector<double> azimuth_deg, order, roll_length, z;
  Bins azimuth, by_order, roll, face;
  Bins tooth[2];                    // left, right
  std::vector<AxisStructure> axes;  // sorted by ratio, largest first
  double mean_before = 0.0;
  double first_tenth = 0.0, last_tenth = 0.0;  // mean residual in the first / last tenth of order
};

ReportData report_data(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  const std::vector<ResidualPoint>& pts = in.residuals.points;
  ReportData r;
  r.n = static_cast<int>(pts.size());
  r.sigma = d.noise.sigma_um;
  r.before = d.residual_before_um;
  r.after = d.residual_after_um;
  if (static_cast<int>(r.before.size()) != r.n) r.before.assign(r.n, 0.0);
  if (static_cast<int>(r.after.size()) != r.n) r.after = r.before;
  const InvoluteGear gear(in.model.gear);
  const double base_radius = gear.base_diameter_mm() / 2.0;
  std::vector<long> k_az, k_order(r.n), k_i, k_j;
  for (int k = 0; k < r.n; ++k) {
    const ResidualPoint& p = pts[k];
    r.fitted_part.push_back(r.before[k] - r.after[k]);
    double deg = p.context.azimuth_rad * 180.0 / kPi;
    deg = std::fmod(deg, 360.0);
    if (deg < 0.0) deg += 360.0;
    r.azimuth_deg.push_back(deg);
    k_az.push_back(static_cast<long>(deg / 5.0));
    r.order.push_back(p.order);
    const double radius = std::hypot(p.context.p.x(), p.context.p.y());
    r.roll_length.push_back(std::sqrt(std::max(0.0, radius * radius - base_radius * base_radius)));
    r.z.push_back(p.context.p.z());
    k_i.push_back(p.i);
    k_j.push_back(p.j);
    r.mean_before += r.before[k] / std::max(1, r.n);
  }
  // Measurement order: up to 60 groups of equal size by rank of the order column.
  std::vector<int> rank(r.n);
  for (int k = 0; k < r.n; ++k) rank[k] = k;
  std::stable_sort(rank.begin(), rank.end(),
                   [&](int a, int b) { return pts[a].order < pts[b].order; });
  const long groups = std::min<long>(60, std::max(1, r.n));
  double first = 0.0, last = 0.0;
  int n_first = 0, n_last = 0;
  for (int q = 0; q < r.n; ++q) {
    k_order[rank[q]] = static_cast<long>(q) * groups / std::max(1, r.n);
    if (q < r.n / 10) first += r.before[rank[q]], ++n_first;
    if (q >= r.n - r.n / 10) last += r.before[rank[q]], ++n_last;
  }
  r.first_tenth = n_first ? first / n_first : 0.0;
  r.last_tenth = n_last ? last / n_last : 0.0;
  r.azimuth = binned(k_az, r.azimuth_deg, r.before, r.after);
  r.by_order = binned(k_order, r.order, r.before, r.after);
  r.roll = binned(k_i, r.roll_length, r.before, r.after);
  r.face = binned(k_j, r.z, r.before, r.after);
  for (int s = 0; s < 2; ++s) {
    std::vector<long> key;
    std::vector<double> x, b, a;
    for (int k = 0; k < r.n; ++k) {
      if ((pts[k].side == FlankSide::kRight) != (s == 1)) continue;
      key.push_back(pts[k].tooth);
      x.push_back(pts[k].tooth);
      b.push_back(r.before[k]);
      a.push_back(r.after[k]);
    }
    r.tooth[s] = binned(key, x, b, a);
  }
  // Tooth structure: both sides' bins together.
  Bins teeth = r.tooth[0];
  for (std::size_t k = 0; k < r.tooth[1].x.size(); ++k) {
    teeth.x.push_back(r.tooth[1].x[k]);
    teeth.before.push_back(r.tooth[1].before[k]);
    teeth.after.push_back(r.tooth[1].after[k]);
    teeth.count.push_back(r.tooth[1].count[k]);
  }
  r.axes = {axis_structure("approach azimuth", r.azimuth, r.sigma),
            axis_structure("measurement order", r.by_order, r.sigma),
            axis_structure("tooth and flank side", teeth, r.sigma),
            axis_structure("roll length (profile position)", r.roll, r.sigma),
            axis_structure("face position z", r.face, r.sigma)};
  std::stable_sort(
      r.axes.begin(), r.axes.end(),
      [](const AxisStructure& a, const AxisStructure& b) { return a.ratio > b.ratio; });
  return r;
}

// The harmonic orders ≥ 1 of the "before" spectrum above their 95 % null band, strongest first.
std::vector<int> orders_above_null(const Diagnosis& d) {
  std::vector<int> orders;
  for (std::size_t k = 1; k < d.spectrum_before_um.size(); ++k) {  // order 0 is the mean
    if (k < d.spectrum_null95_before_um.size() &&
        d.spectrum_before_um[k] > d.spectrum_null95_before_um[k] &&
        std::isfinite(d.spectrum_null95_before_um[k])) {
      orders.push_back(static_cast<int>(k));
    }
  }
  std::stable_sort(orders.begin(), orders.end(), [&](int a, int b) {
    return d.spectrum_before_um[a] / d.spectrum_null95_before_um[a] >
           d.spectrum_before_um[b] / d.spectrum_null95_before_um[b];
  });
  return orders;
}

std::string spectrum_phrase(const Diagnosis& d, int order) {
  std::string s = "order " + std::to_string(order) + " of the azimuth spectrum is " +
                  fixed(d.spectrum_before_um[order]) + " µm";
  if (static_cast<std::size_t>(order) < d.spectrum_null95_before_um.size()) {
    s += ", its 95 % null band " + fixed(d.spectrum_null95_before_um[order]) + " µm";
  }
  return s;
}

// Where the named effect shows, in its own terms.
std::string effect_where(const FittedEffect& e, const Diagnosis& d, const ReportData& r) {
  const std::string& name = e.name;
  if (name == "probe_lobing") {
    int best = -1;
    double largest = 0.0;
    for (const FittedValue& v : e.parameters) {
      int k = 0;
      if (v.estimable && std::sscanf(v.name.c_str(), "amplitude_%d_um", &k) == 1 &&
          v.value > largest) {
        largest = v.value;
        best = k;
      }
    }
    if (best > 0 && static_cast<std::size_t>(best) < d.spectrum_before_um.size()) {
      return "against the approach azimuth, a " + std::to_string(best) + "-fold pattern (" +
             spectrum_phrase(d, best) + ")";
    }
    return "against the approach azimuth";
  }
  if ((name == "step_quantization" || name == "noise") && e.absolute) {
    const PointLawStage& st = d.point_law;
    std::string s =
        "in the spread of single readings: the second differences along the scans "
        "give " +
        fixed(std::sqrt(st.white_variance_um2)) +
        " µm per reading where the model "
        "says " +
        fixed(std::sqrt(st.model_variance_um2)) + " µm";
    if (name == "step_quantization") {
      s += ", with a flat-topped shape and a constant shift (mean residual " +
           fixed(r.mean_before) + " µm) tied to it";
      const PointLawHypothesis* noise = st.find("noise");
      if (noise && st.chosen > 0 && st.best().tied) {
        s += " (a stylus radius error plus a larger noise gives the same shift and spread with "
             "one parameter more, ΔBIC " +
             fixed(noise->bic - st.best().bic, 0) + " worse)";
      }
    }
    return s;
  }
  if (name == "stylus_radius" || name == "step_quantization") {
    return "a constant shift of every reading (mean residual " + fixed(r.mean_before) + " µm)";
  }
  if (name == "scale" || name == "thermal_expansion") {
    return "a size error: the residual follows the distance from the gear centre along the "
           "normal (mean residual " +
           fixed(r.mean_before) + " µm, varying around the gear and between the flank sides)";
  }
  if (name == "drift") {
    return "along the measurement order: the mean residual goes from " + fixed(r.first_tenth) +
           " µm in the first tenth of the sequence to " + fixed(r.last_tenth) + " µm in the last";
  }
  if (name == "eccentricity") {
    return "once around the gear: the per-tooth mean follows one sine over the teeth, with "
           "opposite signs on left and right flanks";
  }
  if (name == "squareness") {
    return "with the position along the machine's axes (a shear of the axes)";
  }
  return "in the effect's signature";
}

// The axes along which the bin means vary beyond noise (at most `most`), strongest first.
std::string axes_phrase(const ReportData& r, int most) {
  std::string s;
  int shown = 0;
  for (const AxisStructure& a : r.axes) {
    if (a.ratio < 4.0 || shown == most) break;
    s += shown == 0 ? "most visible against " : "; then against ";
    s += a.axis + " (bin means " + fixed(a.rms_um) + " µm RMS, noise alone " +
         fixed(a.noise_rms_um) + " µm)";
    ++shown;
  }
  return s;
}

// Where, without naming an effect: axes, the strongest harmonic, a constant shift.
std::string generic_where(const ReportData& r, const Diagnosis& d) {
  std::string s = axes_phrase(r, 2);
  const std::vector<int> orders = orders_above_null(d);
  if (!orders.empty() &&
      d.spectrum_before_um[orders.front()] > 2.0 * d.spectrum_null95_before_um[orders.front()]) {
    s += (s.empty() ? "" : "; ") + std::string("strongest harmonic: ") +
         spectrum_phrase(d, orders.front());
  }
  if (std::abs(r.mean_before) > 4.0 * r.sigma / std::sqrt(std::max(1, r.n))) {
    s += (s.empty() ? "" : "; ") + std::string("mean residual ") + fixed(r.mean_before) + " µm";
  }
  return s;
}

std::string gap_phrase(const GapStatistics& g, double sigma, int replicates) {
  return "residual RMS " + fixed(g.rms_um) + " µm against a noise floor of " + fixed(sigma) +
         " µm (χ²/dof " + fixed(g.chi2_dof, 2) + ", " + p_text(g.chi2_p, replicates) +
         "; KS distance " + fixed(g.ks, 3) + ", " + p_text(g.ks_p, replicates) + ")";
}

// ", X µm with the fitted <effect>" when a point-law effect widened the noise floor.
std::string floor_after_phrase(const Diagnosis& d) {
  for (const FittedEffect& e : d.effects) {
    if (e.absolute) {
      return ", " + fixed(d.noise_floor_after_um) + " µm with the fitted " + e.name + "'s spread";
    }
  }
  return "";
}

std::string points_phrase(const DiagnosisReportInput& in) {
  std::ostringstream s;
  s << in.diagnosis.points << " readings of " << in.readings_path << " against the model "
    << in.model.name << " (" << in.model_path << ")";
  return s.str();
}

}  // namespace

std::string diagnosis_verdict(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  const ReportData r = report_data(in);
  const int k = d.null_replicates;
  std::ostringstream s;
  if (d.status != "tested") {
    s << "No verdict: " << d.status_reason << ". Nothing was tested; fitted.yaml is the model "
      << "unchanged. Give the model its noise (e.g. effects: noise: {sigma_um: …}) or more "
      << "readings.";
    return s.str();
  }
  if (!d.gap_detected) {
    s << "No gap: the readings agree with the model within the noise floor. " << points_phrase(in)
      << ": " << gap_phrase(d.gap_before, r.sigma, k) << ". ";
    const CandidateTest* best = nullptr;
    if (!d.selection.steps.empty()) {
      for (const CandidateTest& t : d.selection.steps.front().tests) {
        if (std::isfinite(t.delta_bic) && (!best || t.delta_bic < best->delta_bic)) best = &t;
      }
    }
    s << "No effect of the library passes the selection";
    if (best) {
      s << " (closest: " << best->name << ", ΔBIC " << fixed(best->delta_bic, 1) << ", "
        << p_text(best->p_null, k) << ", it would remove " << fixed(best->effect_rms_um)
        << " µm RMS)";
    }
    s << ". fitted.yaml is the model unchanged.";
    return s.str();
  }
  const std::string where = generic_where(r, d);
  if (!is_library_effect(d.named_effect)) {
    s << "Gap found, not explained by the effect library: unexplained structure remains. What "
         "disagreed: "
      << points_phrase(in) << ", " << gap_phrase(d.gap_before, r.sigma, k) << ". ";
    if (!where.empty()) s << "Where: " << where << ". ";
    if (d.effects.empty()) {
      s << "No library effect passes the selection";
    } else {
      s << "The selected library effects (";
      for (std::size_t e = 0; e < d.effects.size(); ++e) s << (e ? ", " : "") << d.effects[e].name;
      s << ") explain only " << fixed(100.0 * d.explained_fraction, 0)
        << " % of the excess variance (RMS " << fixed(d.gap_before.rms_um) << " → "
        << fixed(d.gap_after.rms_um) << " µm)";
    }
    s << ". fitted.yaml is the model unchanged; the plots below show the structure to look for "
         "outside the library (the artefact itself, a form or fixture effect).";
    return s.str();
  }
  const FittedEffect& e = d.effects.front();
  s << "Gap found, explained by " << e.name << ". What disagreed: " << points_phrase(in) << ", "
    << gap_phrase(d.gap_before, r.sigma, k) << ". Where: " << effect_where(e, d, r);
  const std::string axes = axes_phrase(r, 1);
  if (!axes.empty()) s << "; " << axes;
  s << ". Which effect, how big: " << e.name << " with " << parameter_list(e, ", ") << " (ΔBIC "
    << fixed(e.evidence.delta_bic, 0) << ", " << p_text(e.evidence.p_null, k) << ")";
  for (std::size_t x = 1; x < d.effects.size(); ++x) {
    s << ", together with " << d.effects[x].name << " with " << parameter_list(d.effects[x], ", ");
  }
  s << ". ";
  if (!d.ambiguous_with.empty()) {
    s << "On this probing plan it cannot be told apart from ";
    for (std::size_t a = 0; a < d.ambiguous_with.size(); ++a) {
      s << (a ? ", " : "") << d.ambiguous_with[a];
    }
    // The distinct measurements that would separate them (at most two; all in the table below).
    std::vector<std::string> separate;
    for (const Ambiguity& a : e.ambiguous) {
      if (separate.size() < 2 &&
          std::find(separate.begin(), separate.end(), a.separate_by) == separate.end()) {
        separate.push_back(a.separate_by);
      }
    }
    for (std::size_t a = 0; a < separate.size(); ++a) {
      s << (a == 0 ? "; to separate them, " : "; and ") << separate[a];
    }
    s << ". ";
  }
  s << "Gap: RMS " << fixed(d.gap_before.rms_um) << " µm → " << fixed(d.gap_after.rms_um)
    << " µm with it, " << fixed(d.held_out_rms_um) << " µm on held-out teeth, noise floor "
    << fixed(r.sigma) << " µm" << floor_after_phrase(d) << " (it explains "
    << fixed(100.0 * d.explained_fraction, 0) << " % of the excess variance). ";
  if (d.unexplained_structure) {
    s << "Unexplained structure remains after it (χ²/dof " << fixed(d.gap_after.chi2_dof, 2) << ", "
      << p_text(d.gap_after.chi2_p, k) << "; KS " << p_text(d.gap_after.ks_p, k) << "). ";
  }
  s << "fitted.yaml is the model with it added.";
  return s.str();
}

std::vector<std::string> diagnosis_summary_lines(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  std::vector<std::string> lines;
  lines.push_back("gearmc diagnose: " + std::to_string(d.points) + " readings of " +
                  in.readings_path + " against " + in.model.name + ", noise floor " +
                  fixed(d.noise.sigma_um) + " µm (" + d.noise.source + ")");
  std::string verdict;
  if (d.status != "tested") {
    verdict = "no verdict: " + d.status_reason;
  } else if (!d.gap_detected) {
    verdict = "no gap: the readings agree with the model within the noise floor";
  } else if (!is_library_effect(d.named_effect)) {
    verdict = "gap, unexplained structure remains: no library effect explains it";
  } else {
    const FittedEffect& e = d.effects.front();
    verdict = "gap: " + e.name + " (" + parameter_list(e, ", ") + ")";
    if (!d.ambiguous_with.empty()) {
      verdict += ", ambiguous with";
      for (const std::string& a : d.ambiguous_with) verdict += " " + a;
    }
    if (d.unexplained_structure) verdict += "; unexplained structure remains";
  }
  lines.push_back(verdict);
  lines.push_back("residual RMS " + fixed(d.gap_before.rms_um) + " µm before, " +
                  fixed(d.gap_after.rms_um) + " µm after (held-out " + fixed(d.held_out_rms_um) +
                  " µm, noise floor " + fixed(d.noise.sigma_um) + " µm" + floor_after_phrase(d) +
                  ")");
  return lines;
}

std::string diagnosis_report_html(const DiagnosisReportInput& in) {
  const Diagnosis& d = in.diagnosis;
  const ReportData r = report_data(in);
  const int k = d.null_replicates;
  const bool fitted_any = !d.effects.empty();
  HtmlReport report("gearmc diagnose: " + in.model.name + " vs " + in.readings_path);
  report.heading("Verdict");
  report.paragraph(diagnosis_verdict(in));
  report.paragraph(
      "Residual = measured − predicted deviation along the nominal flank normal (µm, + = "
      "material side outward). \"Before\" is against the model as given; \"after\" with the "
      "selected effects fitted. The plots show bin means (lines) so a pattern stands out of the "
      "noise; the held-out RMS fits on odd teeth and evaluates on even ones, and the other way "
      "round.");

  // --- Residuals against approach azimuth ---
  report.heading("Where: residuals against the approach azimuth");
  {
    std::vector<Series> series;
    // A bounded number of marks: bin means use every point, the grey marks a sample of them.
    const std::vector<std::size_t> shown = plotted_sample(r.before, kMaxScatterMarks, d.seed);
    Series each{"each point, before", {}, {}, SeriesStyle::kPoints, kRawColour};
    for (std::size_t q : shown) {
      each.x.push_back(r.azimuth_deg[q]);
      each.y.push_back(r.before[q]);
    }
    if (shown.size() < r.before.size()) {
      each.label = "sample of " + std::to_string(shown.size()) + " points, before";
    }
    series.push_back(std::move(each));
    series.push_back(
        {"mean per 5°, before", r.azimuth.x, r.azimuth.before, SeriesStyle::kLine, kBefore});
    if (fitted_any) {
      series.push_back(
          {"mean per 5°, after", r.azimuth.x, r.azimuth.after, SeriesStyle::kLine, kAfter});
      std::vector<double> fitted(r.azimuth.x.size());
      for (std::size_t b = 0; b < fitted.size(); ++b) {
        fitted[b] = r.azimuth.before[b] - r.azimuth.after[b];
      }
      series.push_back({"fitted effect", r.azimuth.x, fitted, SeriesStyle::kLine, kFitted});
    }
    XYPlotOptions o;
    o.title = "Residual vs approach azimuth φ";
    o.x_label = "approach azimuth φ = atan2(−n_y, −n_x), deg";
    o.y_label = "residual, µm";
    o.x_min = 0.0;
    o.x_max = 360.0;
    o.horizontal_lines = {0.0};
    report.figure(
        xy_plot_svg(series, o),
        (shown.size() < r.before.size()
             ? "A sample of " + std::to_string(shown.size()) + " of the " + std::to_string(r.n) +
                   " readings (grey: the smallest and largest residual and a random "
                   "sample of the others)"
             : std::string("Every reading (grey)")) +
            " and the mean per 5° of azimuth of every reading before and after the "
            "fit.");
  }
  {
    std::vector<double> angle, before, after;
    std::map<long, std::pair<double, double>> sum;
    std::map<long, int> count;
    for (int q = 0; q < r.n; ++q) {
      const long key = static_cast<long>(r.azimuth_deg[q] / 10.0);
      sum[key].first += r.before[q];
      sum[key].second += r.after[q];
      ++count[key];
    }
    for (const auto& [key, s] : sum) {
      angle.push_back((static_cast<double>(key) + 0.5) * 10.0 * kPi / 180.0);
      before.push_back(s.first / count[key]);
      after.push_back(s.second / count[key]);
    }
    if (!angle.empty()) {  // close the loop
      angle.push_back(angle.front() + 2.0 * kPi);
      before.push_back(before.front());
      after.push_back(after.front());
    }
    std::vector<PolarSeries> polar;
    polar.push_back({"mean per 10°, before", angle, before, SeriesStyle::kLineAndPoints, kBefore});
    if (fitted_any) {
      polar.push_back({"mean per 10°, after", angle, after, SeriesStyle::kLineAndPoints, kAfter});
    }
    PolarPlotOptions o;
    o.title = "Residual around the approach directions";
    o.radius_label = "mean residual, µm (the centre is the smallest value, not 0)";
    report.figure(polar_plot_svg(polar, o),
                  "Polar view: angle = approach azimuth, radius = mean residual per 10°. A probe "
                  "lobing shows as lobes, a constant shift as a circle off the zero ring.");
  }

  // --- Spectrum ---
  report.heading("Harmonic spectrum against approach azimuth", 3);
  if (!d.spectrum_before_um.empty()) {
    std::vector<double> orders;
    for (std::size_t o = 0; o < d.spectrum_before_um.size(); ++o) {
      orders.push_back(static_cast<double>(o));
    }
    std::vector<Series> series;
    series.push_back(
        {"before", orders, d.spectrum_before_um, SeriesStyle::kLineAndPoints, kBefore});
    if (!d.spectrum_null95_before_um.empty()) {
      series.push_back({"95 % null band, before", orders, d.spectrum_null95_before_um,
                        SeriesStyle::kLine, kNullBefore});
    }
    if (fitted_any) {
      series.push_back({"after", orders, d.spectrum_after_um, SeriesStyle::kLineAndPoints, kAfter});
      if (!d.spectrum_null95_after_um.empty()) {
        series.push_back({"95 % null band, after", orders, d.spectrum_null95_after_um,
                          SeriesStyle::kLine, kNullAfter});
      }
    }
    XYPlotOptions o;
    o.title = "Amplitude of each harmonic order of the residual vs φ";
    o.x_label = "order k (cycles per turn of the approach direction)";
    o.y_label = "amplitude, µm";
    o.y_from_zero = true;
    o.x_min = 0.0;
    o.x_max = orders.back();
    std::string caption =
        "Least-squares amplitude of cos kφ, sin kφ (order 0 = mean). The null band is the 95 % "
        "quantile of each order's amplitude in " +
        std::to_string(k) +
        " simulations of pure noise at the noise floor; an order well above it is structure.";
    if (k == 0) caption = "Least-squares amplitude of cos kφ, sin kφ (order 0 = mean).";
    report.figure(xy_plot_svg(series, o), caption);
  }

  // --- Order, tooth, position ---
  report.heading("Residuals against measurement order, tooth and position", 3);
  auto line_plot = [&](const Bins& b, const std::string& title, const std::string& x_label,
                       const std::string& caption, const std::string& what) {
    std::vector<Series> series;
    series.push_back(
        {"mean " + what + ", before", b.x, b.before, SeriesStyle::kLineAndPoints, kBefore});
    if (fitted_any) {
      series.push_back(
          {"mean " + what + ", after", b.x, b.after, SeriesStyle::kLineAndPoints, kAfter});
    }
    XYPlotOptions o;
    o.title = title;
    o.x_label = x_label;
    o.y_label = "mean residual, µm";
    o.horizontal_lines = {0.0};
    report.figure(xy_plot_svg(series, o), caption);
  };
  line_plot(r.by_order, "Residual vs measurement order", "order (file's order column)",
            "Mean residual of consecutive groups of readings (up to 60 groups of equal size). "
            "Drift shows as a trend.",
            "per group");
  {
    std::vector<Series> series;
    const char* side_name[2] = {"L", "R"};
    for (int s = 0; s < 2; ++s) {
      if (r.tooth[s].x.empty()) continue;
      series.push_back({std::string("flank ") + side_name[s] + ", before", r.tooth[s].x,
                        r.tooth[s].before, SeriesStyle::kLineAndPoints,
                        s == 0 ? kBefore : kNullBefore});
    }
    if (fitted_any) {
      for (int s = 0; s < 2; ++s) {
        if (r.tooth[s].x.empty()) continue;
        series.push_back({std::string("flank ") + side_name[s] + ", after", r.tooth[s].x,
                          r.tooth[s].after, SeriesStyle::kLineAndPoints,
                          s == 0 ? kAfter : kNullAfter});
      }
    }
    XYPlotOptions o;
    o.title = "Residual vs tooth";
    o.x_min = 0.0;
    o.x_max = in.model.gear.teeth + 1.0;
    o.x_label = "tooth (1 on +X, counter-clockwise)";
    o.y_label = "mean residual, µm";
    o.horizontal_lines = {0.0};
    report.figure(xy_plot_svg(series, o),
                  "Mean residual per tooth and flank side. Eccentricity shows as one sine over "
                  "the teeth, opposite on left and right flanks.");
  }
  line_plot(r.roll, "Residual vs roll length", "roll length L, mm",
            "Mean residual per profile position (grid index i).", "per profile position");
  line_plot(r.face, "Residual vs face position", "z, mm",
            "Mean residual per face section (grid index j).", "per face section");
  {
    HtmlTable t;
    t.caption =
        "Structure along each axis (before the fit): RMS of the bin means about their mean, and "
        "what noise alone gives; ratio = χ² of the bin means per degree of freedom (≈ 1 for "
        "noise).";
    t.header = {"axis", "bin means RMS, µm", "noise alone, µm", "ratio"};
    for (const AxisStructure& a : r.axes) {
      t.rows.push_back(
          {{a.axis, fixed(a.rms_um), fixed(a.noise_rms_um), fixed(a.ratio, 1)}, a.ratio >= 4.0});
    }
    report.table(t);
  }

  // --- Gap before / after ---
  report.heading("Gap before and after");
  {
    HtmlTable t;
    t.caption = "Gap statistics (p-values from " + std::to_string(k) +
                " simulations of the null: noise at the noise floor at the same points).";
    t.header = {"", "before", "after"};
    t.rows.push_back({{"residual RMS, µm", fixed(d.gap_before.rms_um), fixed(d.gap_after.rms_um)}});
    t.rows.push_back({{"held-out RMS (odd ↔ even teeth), µm", "", fixed(d.held_out_rms_um)}});
    t.rows.push_back(
        {{"noise floor σ, µm", fixed(d.noise.sigma_um), fixed(d.noise_floor_after_um)}});
    t.rows.push_back({{"excess RMS √(RMS² − σ²), µm", fixed(d.gap_before.excess_rms_um),
                       fixed(d.gap_after.excess_rms_um)}});
    t.rows.push_back(
        {{"χ²/dof (dof)",
          fixed(d.gap_before.chi2_dof, 3) + " (" + std::to_string(d.gap_before.dof) + ")",
          fixed(d.gap_after.chi2_dof, 3) + " (" + std::to_string(d.gap_after.dof) + ")"}});
    t.rows.push_back(
        {{"χ² p-value", p_text(d.gap_before.chi2_p, k), p_text(d.gap_after.chi2_p, k)}});
    t.rows.push_back(
        {{"KS distance to the point law", fixed(d.gap_before.ks, 4), fixed(d.gap_after.ks, 4)}});
    t.rows.push_back({{"KS p-value", p_text(d.gap_before.ks_p, k), p_text(d.gap_after.ks_p, k)}});
    auto interval = [](const GapStatistics& g) {
      return std::isfinite(g.rms_lo_um) ? fixed(g.rms_lo_um) + " – " + fixed(g.rms_hi_um) : "–";
    };
    t.rows.push_back({{"RMS 95 % interval (bootstrap over teeth), µm", interval(d.gap_before),
                       interval(d.gap_after)}});
    t.rows.push_back({{"energy distance to a model simulation, µm",
                       fixed(d.gap_before.energy_um, 4), fixed(d.gap_after.energy_um, 4)}});
    t.rows.push_back({{"energy p-value (whole flanks swapped)", p_text(d.gap_before.energy_p, k),
                       p_text(d.gap_after.energy_p, k)}});
    report.table(t);
    std::ostringstream floor;
    floor << "Noise floor " << fixed(d.noise.sigma_um) << " µm from " << d.noise.source
          << " (model's own noise " << fixed(d.noise.model_um)
          << " µm; robust estimate from the residuals' second differences along the scans "
          << fixed(d.noise.robust_um) << " µm from " << d.noise.differences << " differences).";
    report.paragraph(floor.str());
  }

  // --- Spread of single readings (point-law stage) ---
  report.heading("Spread of single readings");
  {
    const PointLawStage& st = d.point_law;
    if (!st.ran) {
      report.paragraph("Not tested: " + st.skipped_because + ".");
    } else {
      std::ostringstream text;
      text << "Effects that change the law of each reading rather than its mean: a probing noise "
              "larger than the model's, or the servo step quantisation (a latch delay uniform on "
              "[0, q), whose mean −q/2 is the constant shift of a stylus radius error and whose "
              "spread q²/12 is what tells them apart). The second differences along the scans "
              "(structure linear along a scan cancels) give "
           << fixed(std::sqrt(st.white_variance_um2)) << " µm per reading against the model's "
           << fixed(std::sqrt(st.model_variance_um2)) << " µm (" << p_text(st.white_p, k)
           << ", from " << st.differences << " differences).";
      report.paragraph(text.str());
      HtmlTable t;
      t.caption =
          "Laws of a single reading compared by BIC (with the selected effects' columns; a tied "
          "step drops their constant shift and explains it by its mean −q/2). Accepted: white "
          "excess variance, mostly white, ΔBIC ≤ −10.";
      t.header = {"law", "fitted, µm", "σ of a reading, µm", "parameters", "ΔBIC", "accepted"};
      for (std::size_t h = 0; h < st.hypotheses.size(); ++h) {
        const PointLawHypothesis& x = st.hypotheses[h];
        std::string label = x.name == "model"   ? "the model's"
                            : x.name == "noise" ? "noise σ fitted"
                            : x.tied            ? "step q fitted, tied to the shift"
                                                : "step q fitted, with a free shift";
        std::string fitted = "–";
        if (h > 0)
          fitted = (x.name == "noise" ? "σ = " : "q = ") + with_error(x.estimate, x.std_error);
        t.rows.push_back({{label, fitted, fixed(std::sqrt(x.law.variance_um2())),
                           std::to_string(x.parameters), h > 0 ? fixed(x.delta_bic, 1) : "0",
                           h == 0 ? "" : (x.accepted ? "yes" : "no: " + x.note)},
                          static_cast<int>(h) == st.chosen && st.chosen > 0});
      }
      report.table(t);
    }
  }

  // --- Fitted effects ---
  report.heading("Fitted effects");
  if (d.effects.empty()) {
    report.paragraph("No effect was selected.");
  } else {
    HtmlTable t;
    t.caption =
        "Fitted physical parameters (increments on the model's own values of the effect), with "
        "standard errors from the joint least-squares fit (σ̂² = RSS/(n − p)).";
    t.header = {"effect", "parameter", "value ± standard error", "unit", "note"};
    for (const FittedEffect& e : d.effects) {
      for (const FittedValue& v : e.parameters) {
        t.rows.push_back(
            {{e.name, v.name, v.estimable ? with_error(v.value, v.std_error) : "–", v.unit,
              !v.estimable ? "not observable on this plan"
              : e.absolute ? "the effect's own value (point-law stage, standard "
                             "error from the profile likelihood)"
                           : ""},
             e.name == d.named_effect});
      }
    }
    report.table(t);
  }

  // --- Selection table ---
  report.heading("Selection");
  report.paragraph(
      "Forward selection over the effect library: at each step every candidate not yet selected "
      "is tested as an addition. It is accepted only when it is significant (Holm-adjusted F "
      "test and the null-calibrated p below α = " +
      general(d.alpha) +
      "), strongly supported (ΔBIC ≤ −10) and practically relevant (it removes at least a "
      "quarter of the noise floor in RMS); the best such candidate by ΔBIC is taken.");
  for (std::size_t s = 0; s < d.selection.steps.size(); ++s) {
    const SelectionStep& step = d.selection.steps[s];
    HtmlTable t;
    std::string before;
    for (int c : step.selected_before) {
      before += (before.empty() ? "" : ", ") + d.candidate_names.at(c);
    }
    t.caption = "Step " + std::to_string(s + 1) +
                (before.empty() ? "" : " (given " + before + ")") + ": " +
                (step.accepted >= 0 ? step.tests[step.accepted].name + " accepted"
                                    : std::string("nothing accepted, selection stops"));
    t.header = {"candidate", "columns",         "F",           "p (F, Holm)", "p (null)",
                "ΔBIC",      "removes RMS, µm", "significant", "ΔBIC ≤ −10",  "practical"};
    for (std::size_t c = 0; c < step.tests.size(); ++c) {
      const CandidateTest& test = step.tests[c];
      auto yes = [](bool b) { return std::string(b ? "yes" : "no"); };
      std::string name = test.name;
      if (!test.note.empty()) name += " (" + test.note + ")";
      t.rows.push_back(
          {{name, std::to_string(test.added_rank), general(test.f), general(test.p_holm),
            p_text(test.p_null, k), fixed(test.delta_bic, 1), fixed(test.effect_rms_um),
            yes(test.significant), yes(test.bic_support), yes(test.practical)},
           static_cast<int>(c) == step.accepted});
    }
    report.table(t);
  }

  // --- Ambiguity ---
  report.heading("Ambiguity");
  bool any_ambiguity = false;
  for (const FittedEffect& e : d.effects) {
    if (e.ambiguous.empty()) {
      report.paragraph(e.name +
                       " is identified on this probing plan: no other candidate reproduces its "
                       "fitted contribution (signal correlation ≤ 0.9) and none came within "
                       "ΔBIC 6 of it.");
      continue;
    }
    any_ambiguity = true;
    HtmlTable t;
    t.caption = e.name + " cannot be told apart from:";
    t.header = {"other effect",
                "reason",
                "signal correlation",
                "canonical correlation",
                "condition number",
                "ΔBIC gap",
                "measurement that would separate them"};
    for (const Ambiguity& a : e.ambiguous) {
      t.rows.push_back(
          {{a.with, a.reason, fixed(a.signal_correlation), fixed(a.canonical_correlation),
            general(a.condition_number), fixed(a.delta_bic_gap, 1), a.separate_by}});
    }
    report.table(t);
  }
  if (d.effects.empty())
    report.paragraph("No effect was selected, so there is nothing to separate.");
  (void)any_ambiguity;

  // --- Histograms ---
  report.heading("Distribution of the residuals before and after");
  if (r.n > 0) {
    // Bins from the central quantiles of both residual sets, never from their full range.
    std::vector<double> both = r.before;
    if (fitted_any) both.insert(both.end(), r.after.begin(), r.after.end());
    const DisplayBins bins_of = display_bins(both, r.sigma);
    both = {};
    const double start = bins_of.lo_um, width = bins_of.width_um;
    const std::size_t bins = bins_of.bins;
    const double sigma = r.sigma;
    for (int which = 0; which < (fitted_any ? 2 : 1); ++which) {
      Histogram h(start, width, bins);
      for (double v : which == 0 ? r.before : r.after) h.add(v);
      HistogramPlotOptions o;
      o.title = std::string("Residuals ") + (which == 0 ? "before" : "after") +
                " the fit (n = " + std::to_string(r.n) + ")";
      o.x_label = "residual, µm";
      o.bars_label = which == 0 ? "before" : "after";
      // The law a residual follows if the model (before) or the fitted model (after) is right:
      // the model's per-point law (Gaussian, or with a step's flat top), centred.
      ResidualLaw law;
      law.sigma_um = sigma;
      if (d.noise.law.variance_um2() > 0.0) law = residual_law(d.noise.law);
      if (which == 1 && d.point_law.chosen > 0) {
        law = d.point_law.best().law;
        law.offset_um -= law.mean_um();
      }
      if (law.variance_um2() > 0.0) {
        o.overlay_pdf = [law](double x) { return std::exp(law.log_density(x)); };
        o.overlay_label = law.width_um > 0.0
                              ? "the law of a reading: N(0, " + fixed(law.sigma_um) +
                                    "²) with a step of " + fixed(law.width_um) + " µm, centred"
                              : "N(0, σ²), σ = " + fixed(law.sigma_um) + " µm";
      }
      o.x_min = start;
      o.x_max = start + width * static_cast<double>(bins);
      std::string caption = which == 0 ? "Residuals against the model as given."
                                       : "Residuals with the selected effects fitted.";
      if (h.underflow() + h.overflow() > 0) {
        caption += " Outside the plotted range: " + std::to_string(h.underflow()) +
                   " below (smallest " + general(h.underflow_min()) + " µm) and " +
                   std::to_string(h.overflow()) + " above (largest " + general(h.overflow_max()) +
                   " µm); the range is the central 99 % of the residuals widened by half its width "
                   "on each side.";
      }
      report.figure(histogram_svg(h, o), caption);
    }
  }

  // --- Notes, inputs, fitted.yaml ---
  std::vector<std::string> notes = d.notes;
  for (const std::string& n : in.fitted.notes) notes.push_back("fitted.yaml: " + n);
  if (!notes.empty()) {
    report.heading("Notes");
    for (const std::string& n : notes) report.paragraph(n + ".");
  }
  report.heading("Inputs");
  {
    std::ostringstream s;
    s << "Model: " << in.model_path << " (scenario " << in.model.name << "), predicted on "
      << (in.residuals.artefact == ArtefactModel::kModelGears ? "the model's perturbed gears"
                                                              : "the model's nominal master gear")
      << ". Readings: " << in.readings_path << ", " << d.points << " points, stylus radius "
      << in.residuals.stylus_radius_mm << " mm";
    if (d.nominal_fallback > 0) s << " (" << d.nominal_fallback << " predicted with p + R n)";
    s << ". Null simulation: " << k << " replicates, seed " << d.seed
      << ", α = " << general(d.alpha) << ".";
    report.paragraph(s.str());
  }
  report.preformatted(in.fitted.yaml, "fitted.yaml");
  return report.html();
}

}  // namespace gearmc

// The `gearmc diagnose` report's section on a production gear's own flank deviations
// (part_model.h): per side, per flank, and the machine effects the part hides on this set-up.
#include <sstream>

#include "engine/apps/diagnose/diagnosis_report_sections.h"

namespace gearmc::diagnose_report {

namespace {

std::string value_text(const PartValue& v) {
  return v.estimable ? fixed(v.value_um, 2) + " ± " + fixed(v.u_um, 2) : "–";
}

std::string side_name(FlankSide side) { return side == FlankSide::kRight ? "right" : "left"; }

}  // namespace

void part_section(HtmlReport& report, const ReportContext& ctx) {
  const PartDeviations& p = ctx.d.part;
  if (!p.fitted) return;
  report.heading("The gear's own deviations");
  std::ostringstream text;
  text << "A production gear (--workpiece production): every model contains, per measured flank, "
          "its position (the mean normal deviation: the tooth's pitch, runout and thickness "
          "along the normal), its profile slope f_Hα and crowning C_α over the measured roll "
          "length, and its helix slope f_Hβ and crowning C_β over the measured face width (ISO "
          "1328-1 and VDI/VDE 2607 terms; + = material outward, slopes from the start of the "
          "range to its end, crowning = the middle above the ends). "
       << p.flanks.size() << " flanks, " << p.rank
       << " parameters, fitted jointly with the selected effects; their RMS over the readings is "
       << fixed(p.fitted_rms_um)
       << " µm. \"Before\" in this report is the model with these "
          "deviations fitted, so every gap is what the gear's own low-order form cannot explain. "
          "U is the expanded uncertainty (k = 2) of the fit, from the residual spread.";
  report.paragraph(text.str());
  HtmlTable sides;
  sides.caption =
      "Per flank side: the means over the measured flanks (f_Hαm, f_Hβm) with the "
      "smallest and largest flank's value, and the positions' range (µm).";
  sides.header = {"side",     "flanks",        "f_Hαm (min … max)", "C_α mean", "f_Hβm (min … max)",
                  "C_β mean", "position range"};
  for (const PartSideSummary& s : p.sides) {
    sides.rows.push_back({{side_name(s.side), std::to_string(s.flanks),
                           fixed(s.f_h_alpha_mean_um, 2) + " (" + fixed(s.f_h_alpha_min_um, 2) +
                               " … " + fixed(s.f_h_alpha_max_um, 2) + ")",
                           fixed(s.c_alpha_mean_um, 2),
                           fixed(s.f_h_beta_mean_um, 2) + " (" + fixed(s.f_h_beta_min_um, 2) +
                               " … " + fixed(s.f_h_beta_max_um, 2) + ")",
                           fixed(s.c_beta_mean_um, 2), fixed(s.position_range_um, 2)}});
  }
  report.table(sides);
  if (!p.confounded.empty()) {
    HtmlTable c;
    c.caption =
        "Machine effects the gear's own deviations hide on this set-up: ρ is the smallest "
        "canonical correlation of the effect's columns with the part's (1: wholly inside, so no "
        "reading can tell them apart; ≥ 0.9: at most √(1 − ρ²) of the effect is left to see).";
    c.header = {"effect", "ρ", "separable", "what separates them"};
    c.last_column_text = true;
    for (const PartConfounding& x : p.confounded) {
      c.rows.push_back({{x.effect, fixed(x.correlation, 4), x.indistinguishable ? "no" : "barely",
                         x.separate_by}});
    }
    report.table(c);
  }
  // The measured ranges and point counts in the caption when every flank has the same (a
  // grid plan), else as columns; the gear column only for several gears.
  const auto range_text = [](double from, double to) {
    return fixed(from, 2) + "–" + fixed(to, 2);
  };
  bool same = true, several_gears = false;
  const PartFlank& first = p.flanks.front().flank;
  for (const PartFlankDeviations& d : p.flanks) {
    const PartFlank& f = d.flank;
    several_gears = several_gears || f.gear != first.gear;
    same = same && f.points == first.points &&
           range_text(f.profile_from_mm, f.profile_to_mm) ==
               range_text(first.profile_from_mm, first.profile_to_mm) &&
           range_text(f.face_from_mm, f.face_to_mm) ==
               range_text(first.face_from_mm, first.face_to_mm);
  }
  HtmlTable flanks;
  flanks.caption = "Every measured flank: value ± U (k = 2), µm";
  if (same) {
    flanks.caption += "; each with " + std::to_string(first.points) + " points over roll length " +
                      range_text(first.profile_from_mm, first.profile_to_mm) + " mm and face " +
                      range_text(first.face_from_mm, first.face_to_mm) + " mm";
  }
  flanks.caption += ".";
  if (several_gears) flanks.header.push_back("gear");
  for (const char* h : {"tooth", "side"}) flanks.header.push_back(h);
  if (!same) {
    for (const char* h : {"points", "roll length, mm", "face, mm"}) flanks.header.push_back(h);
  }
  for (const char* h : {"position", "f_Hα", "C_α", "f_Hβ", "C_β"}) flanks.header.push_back(h);
  for (const PartFlankDeviations& d : p.flanks) {
    const PartFlank& f = d.flank;
    std::vector<std::string> row;
    if (several_gears) row.push_back(std::to_string(f.gear));
    row.push_back(std::to_string(f.tooth));
    row.push_back(side_name(f.side));
    if (!same) {
      row.push_back(std::to_string(f.points));
      row.push_back(range_text(f.profile_from_mm, f.profile_to_mm));
      row.push_back(range_text(f.face_from_mm, f.face_to_mm));
    }
    for (const PartValue* v : {&d.position, &d.f_h_alpha, &d.c_alpha, &d.f_h_beta, &d.c_beta}) {
      row.push_back(value_text(*v));
    }
    flanks.rows.push_back({row});
  }
  report.table(flanks);
}

}  // namespace gearmc::diagnose_report

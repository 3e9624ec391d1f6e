// `gearmc diagnose` (see diagnose_command.h).
#include "engine/cli/diagnose_command.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <vector>

#include "core/input_error.h"
#include "core/number_text.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "engine/apps/diagnose/diagnosis.h"
#include "engine/apps/diagnose/diagnosis_json.h"
#include "engine/apps/diagnose/diagnosis_report.h"
#include "engine/apps/diagnose/fitted_scenario.h"
#include "engine/apps/diagnose/readings_check.h"
#include "engine/effects/cmm_effects.h"
#include "engine/readings/dmis_results.h"
#include "engine/readings/point_matching.h"
#include "engine/readings/point_table.h"
#include "engine/readings/readings_csv.h"
#include "engine/reports/svg_plot.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

namespace fs = std::filesystem;

namespace {

// Appends the readings of file `f` of `paths` to `all` (the readings of the files before it):
// its gears numbered after the last one so far, its rows marked with their file. The files must
// agree on what the rows mean: the stylus radius, calibrated (ref_dev_um) or not, how the labels
// were made (matching or the file's own) and the format (a readings CSV or not).
void append_readings(Readings& all, Readings&& more, const std::vector<std::string>& paths,
                     std::size_t f) {
  const auto refuse = [&](const std::string& what, InputLocation where) {
    throw InputError(where,
                     what + " than " + paths.front() + ": files read together must agree on it");
  };
  const InputLocation file{paths[f], 0, 0};
  if (more.stylus_radius_mm != all.stylus_radius_mm) {
    // Where the file says it: the readings CSV's header line `# stylus_radius_mm=…`.
    InputLocation at = file;
    std::ifstream in(paths[f], std::ios::binary);
    std::string line;
    for (int number = 1; std::getline(in, line) && number <= 16; ++number) {
      if (const std::size_t k = line.find("stylus_radius_mm="); k != std::string::npos) {
        at = {paths[f], number, static_cast<int>(k + 17) + 1};  // 17: "stylus_radius_mm="
        break;
      }
    }
    refuse("stylus_radius_mm: another stylus radius (" + shortest_text(more.stylus_radius_mm) +
               " mm, the first file's " + shortest_text(all.stylus_radius_mm) + " mm)",
           at);
  }
  if (more.has_ref_dev != all.has_ref_dev) refuse("another artefact (ref_dev_um) column", file);
  if (more.labels_from_matching != all.labels_from_matching) refuse("other labels", file);
  if (more.is_readings_csv != all.is_readings_csv) refuse("another file format", file);
  if (f > std::numeric_limits<std::uint16_t>::max()) refuse("more files", file);
  if (all.sources.empty()) all.sources.push_back(paths.front());
  all.sources.push_back(paths[f]);
  int next_gear = 0;
  for (const ReadingRow& row : all.rows) next_gear = std::max(next_gear, row.gear + 1);
  for (ReadingRow& row : more.rows) {
    row.gear += next_gear;
    row.source = static_cast<std::uint16_t>(f);
    all.rows.push_back(row);
  }
  all.feet.insert(all.feet.end(), more.feet.begin(), more.feet.end());
  for (std::string& w : more.warnings) all.warnings.push_back(std::move(w));
}

}  // namespace

int diagnose_command(const DiagnoseCommandOptions& o, std::ostream& out, std::ostream& err) {
  // Inputs first: nothing is created or written unless both are good.
  const Scenario model = load_scenario_file(o.model_path);
  if (model.cmm) {
    // A `cmm:` section is a population of machines that pass a data sheet, not one machine: the
    // model would predict the readings of whichever kept machine the nominal draw names.
    throw InputError(model.cmm->where, "cmm", "",
                     "a model with definite machine effects: diagnose compares readings with one "
                     "machine, and a `cmm:` section describes every machine that passes the data "
                     "sheet (docs/cmm.md) — give the machine's effects under `effects:`, or leave "
                     "the section out to diagnose against the gear and probe alone");
  }
  // A DMIS output file (the results of `gearmc export-plan`'s program): its points were
  // compensated with the ball the model names. With --columns, a CMM's point table, likewise.
  // Each --measured file: a label-free table (columns x, y, z) is matched to the model's flanks
  // first. Several files are repeated measurements of the gear: read together, each file's gears
  // numbered after the previous file's.
  if (o.measured_paths.empty()) throw InputError({"--measured", 0, 0}, "--measured: no file given");
  std::optional<PointTableColumns> columns;
  if (!o.columns_path.empty()) columns = read_point_table_columns(o.columns_path);
  std::optional<MatchingSummary> matching;
  double matched_square_sum = 0.0;
  std::unique_ptr<Readings> readings;
  std::string measured_names;
  for (std::size_t f = 0; f < o.measured_paths.size(); ++f) {
    const std::string& path = o.measured_paths[f];
    measured_names += (f ? " + " : "") + path;
    Readings one;
    if (columns && columns->label_free) {
      const InvoluteGear gear(model.gear);
      MatchingSummary summary;
      one = match_unlabelled_points(gear,
                                    read_unlabelled_points(path, *columns, model.stylus_radius_mm),
                                    nominal_point_allowance_mm(model, gear), &summary);
      MatchingSummary& all = matching ? *matching : matching.emplace();
      all.points += summary.points;
      all.refused += summary.refused;
      all.max_distance_um = std::max(all.max_distance_um, summary.max_distance_um);
      const double matched = static_cast<double>(summary.points - summary.refused);
      matched_square_sum += summary.rms_distance_um * summary.rms_distance_um * matched;
      all.rms_distance_um =
          std::sqrt(matched_square_sum /
                    static_cast<double>(std::max<std::size_t>(1, all.points - all.refused)));
    } else if (columns) {
      one = read_point_table(path, *columns, model.stylus_radius_mm);
    } else {
      one = is_dmis_file(path) ? read_dmis_results(path, model.stylus_radius_mm)
                               : read_readings(path);
    }
    if (!readings) {
      readings = std::make_unique<Readings>(std::move(one));
      continue;
    }
    append_readings(*readings, std::move(one), o.measured_paths, f);
  }
  for (const std::string& w : model.warnings) err << "gearmc: warning: " << w << "\n";
  for (const std::string& w : readings->warnings) err << "gearmc: warning: " << w << "\n";

  DiagnoseOptions options;
  options.prediction.artefact =
      o.model_gears ? ArtefactModel::kModelGears : ArtefactModel::kNominalMaster;
  options.workpiece = o.workpiece == "production" ? Workpiece::kProduction : Workpiece::kMaster;
  if (!o.turned_by.empty()) {
    const InputLocation at{"--turned-by", 0, 0};
    if (options.workpiece != Workpiece::kProduction) {
      throw InputError(at,
                       "--turned-by: set-ups of one gear are read with --workpiece production "
                       "(a master's readings need no turning)");
    }
    std::string item;
    std::istringstream list(o.turned_by);
    while (std::getline(list, item, ',')) {
      std::size_t used = 0;
      int k = 0;
      try {
        k = std::stoi(item, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != item.size() || item.empty() || std::abs(k) > 100000) {
        throw InputError(at, "--turned-by: '" + item +
                                 "' is not a whole number of teeth; expected one integer per "
                                 "measured gear or run, e.g. --turned-by 0,3");
      }
      options.turned_by_teeth.push_back(k);
    }
    int gears = 0;
    for (const ReadingRow& row : readings->rows) gears = std::max(gears, row.gear + 1);
    if (static_cast<int>(options.turned_by_teeth.size()) != gears) {
      throw InputError(at, "--turned-by: " + std::to_string(options.turned_by_teeth.size()) +
                               " value" + (options.turned_by_teeth.size() == 1 ? "" : "s") +
                               " for " + std::to_string(gears) +
                               " measured gears or runs; expected one per gear or run, in "
                               "order (the files' gears follow each other)");
    }
  }
  if (o.null_seed) options.selection.seed = *o.null_seed;
  if (o.null_replicates) options.selection.null_replicates = *o.null_replicates;
  if (!o.candidates.empty()) {
    std::string item;
    std::istringstream list(o.candidates);
    const std::vector<std::string>& names = candidate_effect_names();
    while (std::getline(list, item, ',')) {
      if (std::find(names.begin(), names.end(), item) == names.end()) {
        std::string expected;
        for (const std::string& n : names) expected += (expected.empty() ? "" : ", ") + n;
        throw InputError({"--candidates", 0, 0},
                         "--candidates: unknown effect '" + item +
                             "'; expected a comma-separated list of: " + expected);
      }
      options.candidates.only.push_back(item);
    }
  }
  const PreparedResiduals prepared =
      prepare_residuals(model, *readings, o.measured_paths.front(), options);
  readings.reset();  // the residuals carry what the diagnosis needs (memory at 10⁶ readings)
  const Residuals& residuals = prepared.residuals;
  const Diagnosis diagnosis = diagnose_prepared(prepared, options);

  const fs::path dir(o.out_dir);
  FittedScenario fitted = fitted_scenario(model, diagnosis, o.model_path, measured_names);
  // fitted.yaml must load as a scenario. A fitted value beyond its parameter's physical range
  // (e.g. a "noise" of 1 mm fitted to one gross outlier) is no explanation of the gap: then
  // fitted.yaml is the model unchanged, and the outputs say why.
  std::string fitted_problem;
  try {
    parse_scenario(fitted.yaml, (dir / "fitted.yaml").string());
  } catch (const InputError& e) {
    fitted_problem = e.what();
    fitted.yaml =
        "# gearmc diagnose: the fit is not added to this model, because it is outside\n"
        "# the physical range of its effect:\n# " +
        shown_input(fitted_problem, 400) + "\n" + model.source_text;
  }
  const DiagnosisReportInput report{model,     o.model_path, measured_names, residuals,
                                    diagnosis, fitted,       matching};
  const std::string html = diagnosis_report_html(report);

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw InputError({dir.string(), 0, 0}, dir.string() + ": cannot create the output folder" +
                                               (ec ? ": " + ec.message() : std::string()));
  }
  OutputFiles files(dir);
  // What made these outputs: the model file is the input fingerprinted; the readings file is
  // named in the command line.
  const Provenance made = make_provenance(o.command_line, model.source_path, model.source_text);
  std::string json = diagnosis_json(diagnosis);
  {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(json);
    nlohmann::ordered_json with;
    with["provenance"] = provenance_json(made);
    for (auto& [key, value] : j.items()) with[key] = value;
    json = with.dump(2) + "\n";
  }
  if (matching) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(json);
    j["matching"] = {{"points", matching->points},
                     {"max_distance_um", matching->max_distance_um},
                     {"rms_distance_um", matching->rms_distance_um},
                     {"refused", matching->refused}};
    json = j.dump(2) + "\n";
  }
  if (!fitted_problem.empty()) {
    nlohmann::ordered_json j = nlohmann::ordered_json::parse(json);
    j["fitted_yaml"] = {{"fit_added", false},
                        {"reason", "the fitted value is outside its parameter's physical range: " +
                                       shown_input(fitted_problem, 400)}};
    json = j.dump(2) + "\n";
  }
  files.write("diagnosis.json", json);
  files.write("fitted.yaml", fitted.yaml + "# made by " + provenance_line(made) + "\n");
  const std::string footer = "<p>Made by " + escape_xml(provenance_line(made)) + ".</p>\n</body>";
  std::string page = html;
  if (const std::size_t end = page.rfind("</body>"); end != std::string::npos) {
    page.replace(end, 7, footer);
  }
  files.write("report.html", page);
  files.commit();

  for (const std::string& line : diagnosis_summary_lines(report)) out << line << "\n";
  if (!fitted_problem.empty()) {
    out << "warning: the fit is outside its effect's physical range, so fitted.yaml is the model "
           "unchanged: "
        << shown_input(fitted_problem, 400) << "\n";
  }
  out << "report: " << (dir / "report.html").string() << " (also diagnosis.json, fitted.yaml)\n";
  return 0;
}

}  // namespace gearmc

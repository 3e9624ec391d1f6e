// `gearmc diagnose` (see diagnose_command.h).
#include "engine/cli/diagnose_command.h"

#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <vector>

#include "engine/diagnose/diagnosis.h"
#include "engine/diagnose/diagnosis_json.h"
#include "engine/diagnose/diagnosis_report.h"
#include "engine/diagnose/fitted_scenario.h"
#include "engine/diagnose/readings_check.h"
#include "engine/readings/readings_csv.h"
#include "engine/report/output_files.h"
#include "engine/scenario/input_error.h"
#include "engine/scenario/scenario.h"

namespace gearmc {

namespace fs = std::filesystem;

int diagnose_command(const DiagnoseCommandOptions& o, std::ostream& out) {
  // Inputs first: nothing is created or written unless both are good.
  const Scenario model = load_scenario_file(o.model_path);
  auto readings = std::make_unique<Readings>(read_readings(o.measured_path));

  DiagnoseOptions options;
  options.prediction.artefact =
      o.model_gears ? ArtefactModel::kModelGears : ArtefactModel::kNominalMaster;
  if (o.seed) options.selection.seed = *o.seed;
  if (o.null_replicates) options.selection.null_replicates = *o.null_replicates;
  check_readings_against_model(model, *readings, o.measured_path);
  const Residuals residuals = compute_residuals(model, *readings, options.prediction);
  check_residuals(residuals, *readings, o.measured_path);
  readings.reset();  // the residuals carry what the diagnosis needs (memory at 10⁶ readings)
  const NoiseFloor noise = estimate_noise_floor(model, residuals);
  const Diagnosis diagnosis = diagnose_residuals(residuals, noise, options);

  const fs::path dir(o.out_dir);
  const FittedScenario fitted = fitted_scenario(model, diagnosis, o.model_path, o.measured_path);
  // fitted.yaml must load as a scenario (interface.md); a failure here is a bug, not bad input.
  try {
    parse_scenario(fitted.yaml, (dir / "fitted.yaml").string());
  } catch (const InputError& e) {
    throw std::runtime_error(std::string("fitted.yaml does not load: ") + e.what());
  }
  const DiagnosisReportInput report{model,     o.model_path, o.measured_path,
                                    residuals, diagnosis,    fitted};
  const std::string html = diagnosis_report_html(report);

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw InputError({dir.string(), 0, 0}, dir.string() + ": cannot create the output folder" +
                                               (ec ? ": " + ec.message() : std::string()));
  }
  OutputFiles files(dir);
  files.write("diagnosis.json", diagnosis_json(diagnosis));
  files.write("fitted.yaml", fitted.yaml);
  files.write("report.html", html);
  files.commit();

  for (const std::string& line : diagnosis_summary_lines(report)) out << line << "\n";
  out << "report: " << (dir / "report.html").string() << " (also diagnosis.json, fitted.yaml)\n";
  return 0;
}

}  // namespace gearmc

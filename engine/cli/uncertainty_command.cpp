// `gearmc uncertainty` (see uncertainty_command.h): reads the model, checks the output folder
// and the trial count before any work, evaluates, then writes the outputs atomically.
#include "engine/cli/uncertainty_command.h"
#include "engine/cli/interrupt_guard.h"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "core/output_files.h"
#include "core/provenance.h"
#include "core/ranks.h"
#include "engine/apps/r_test/r_test_evaluation.h"
#include "engine/apps/r_test/r_test_output.h"
#include "engine/apps/r_test/register.h"
#include "engine/apps/uncertainty/evaluation.h"

namespace gearmc {
namespace {

namespace fs = std::filesystem;
using namespace gearmc::uncertainty;

// The default folder results/<name> may hold another model file's results (same `name:`).
void refuse_another_models_folder(const fs::path& dir, const UncertaintyModel& model) {
  std::ifstream previous(dir / "uncertainty.json");
  if (!previous) return;
  const nlohmann::json j = nlohmann::json::parse(previous, nullptr, false);
  if (j.is_discarded() || !j.contains("source") || !j["source"].is_string()) return;
  const std::string source = j["source"].get<std::string>();
  if (source == model.source_path) return;
  throw InputError({model.source_path, 0, 0},
                   dir.string() + " holds the results of another model file with the name '" +
                       model.name + "' (" + source + "); give this one its own folder with " +
                       "--out DIR, or remove " + dir.string());
}

// The r_test builtin model: its own compound evaluation (engine/apps/r_test) with the same folder,
// atomic-output and interrupt rules. Monte-Carlo routes run a fixed M (default 10^6, P3's T).
int r_test_command(const UncertaintyCommandOptions& o, const UncertaintyModel& model,
                   std::uint64_t trials, std::ostream& out, std::ostream& err) {
  const rtest::RTestModel m = rtest::make_r_test_model(model);
  rtest::RTestRunOptions ro;
  ro.trials = trials;
  ro.threads = o.threads;
  ro.cancel = &interrupted_flag();
  CreatedFolder folder;
  folder.dir = o.out_dir.empty() ? fs::path("results") / model.name : fs::path(o.out_dir);
  if (o.out_dir.empty()) refuse_another_models_folder(folder.dir, model);
  prepare_output_folder(folder.dir, &folder.created);
  out << "gearmc uncertainty: " << model.name << " (builtin r_test), " << model.inputs.size()
      << " input classes, p = " << m.coverage_probability << ", seed " << m.seed << ", " << trials
      << " trials per Monte-Carlo route, verification " << m.settings.positions << " positions x "
      << m.settings.repetitions << "\n"
      << std::flush;
  rtest::RTestResult r;
  {
    InterruptGuard guard;
    r = rtest::evaluate_r_test(m, ro);
  }
  if (r.cancelled) {
    err << "gearmc: interrupted; nothing written\n";
    return 130;
  }
  if (const std::string why = rtest::r_test_refusal(r); !why.empty()) {
    throw InputError({model.source_path, 0, 0},
                     model.source_path + ": " + why +
                         "; the input laws are too wide for the R-Test model (P3's errors are a "
                         "few µm): narrow them");
  }
  const Provenance provenance =
      make_provenance(o.command_line, model.source_path, model.source_text);
  OutputFiles files(folder.dir);
  files.write("uncertainty.json", rtest::r_test_json(model, m, r, ro, provenance).dump(2) + "\n");
  files.write("report.html", rtest::r_test_report_html(model, m, r, provenance));
  files.commit();
  folder.created = false;
  rtest::print_r_test(out, m, r);
  for (const std::string& w : r.warnings) err << "gearmc: warning: " << w << "\n";
  out << "report: " << (folder.dir / "report.html").string() << "\n";
  return 0;
}

}  // namespace

int uncertainty_command(const UncertaintyCommandOptions& o, std::ostream& out, std::ostream& err) {
  rtest::register_r_test_model();
  const UncertaintyModel model = load_uncertainty_model(o.model_path);
  McmOptions mcm;
  mcm.seed = o.seed.value_or(model.settings.seed);
  mcm.trials = model.settings.trials;
  mcm.coverage_probability = model.settings.coverage_probability;
  mcm.significant_digits = model.settings.significant_digits;
  mcm.max_trials = model.settings.max_trials;
  mcm.threads = o.threads;
  mcm.cancel = &interrupted_flag();
  if (!o.trials.empty()) {
    if (o.trials == "adaptive") {
      mcm.trials.reset();
    } else {
      const bool digits =
          o.trials.find_first_not_of("0123456789") == std::string::npos && o.trials.size() <= 12;
      if (!digits || o.trials.empty()) {
        throw InputError({}, "--trials", o.trials,
                         "adaptive or a number of trials (digits only, e.g. 1000000)",
                         did_you_mean(o.trials, {"adaptive"}));
      }
      mcm.trials = std::stoull(o.trials);
      check_trials(*mcm.trials, model.outputs.size(), mcm.coverage_probability, {}, "--trials");
    }
  } else if (mcm.trials) {
    check_trials(*mcm.trials, model.outputs.size(), mcm.coverage_probability, model.settings_where,
                 "settings.trials");
  }

  // Only rank 0 of an MPI job writes; the other ranks compute their share of the trials.
  const Ranks ranks = Ranks::world();
  mcm.ranks = &ranks;
  if (model.builtin == "r_test") {
    // The R-Test's routes run in one process: under mpirun, rank 0 alone.
    if (!ranks.is_root()) return 0;
    UncertaintyModel seeded = model;  // --seed overrides settings.seed here too
    seeded.settings.seed = mcm.seed;
    return r_test_command(o, seeded, mcm.trials.value_or(1'000'000), out, err);
  }

  CreatedFolder folder;
  ranks.agree([&] {
    if (!ranks.is_root()) return;
    folder.dir = o.out_dir.empty() ? fs::path("results") / model.name : fs::path(o.out_dir);
    if (o.out_dir.empty()) refuse_another_models_folder(folder.dir, model);
    prepare_output_folder(folder.dir, &folder.created);
  });

  out << "gearmc uncertainty: " << model.name << ", " << model.inputs.size() << " inputs, "
      << model.outputs.size() << " output(s), p = " << mcm.coverage_probability << ", seed "
      << mcm.seed << ", "
      << (mcm.trials ? std::to_string(*mcm.trials) + " trials" : std::string("adaptive trials"));
  if (mcm.trials) {
    // The memory rule of the MCM: 16 bytes per trial per output at most.
    const double mb = kBytesPerTrialPerOutput * static_cast<double>(*mcm.trials) *
                      static_cast<double>(model.outputs.size()) / 1e6;
    out << " (values: up to " << std::setprecision(mb < 10 ? 2 : 3) << mb << " MB)"
        << std::defaultfloat;
  }
  out << "\n" << std::flush;
  const bool show_progress = !o.quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  if (show_progress) {
    mcm.progress = [&](std::uint64_t done, std::uint64_t planned) {
      const double t =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (t < 1.0) return;
      err << "\r  trials " << done;
      if (planned > 0) err << "/" << planned;
      err << "  " << std::scientific << std::setprecision(2) << double(done) / t << " trials/s   "
          << std::defaultfloat << std::flush;
    };
  }
  Evaluation e;
  {
    InterruptGuard guard;
    e = evaluate(model, mcm);
  }
  if (show_progress &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= 1.0) {
    err << "\n";
  }
  if (e.mcm.cancelled) {
    err << "gearmc: interrupted; nothing written\n";
    return 130;
  }
  if (!ranks.is_root()) return 0;
  const Provenance provenance =
      make_provenance(o.command_line, model.source_path, model.source_text);
  OutputFiles files(folder.dir);
  files.write("uncertainty.json", evaluation_json(model, mcm, e, provenance).dump(2) + "\n");
  files.write("report.html", evaluation_report_html(model, mcm, e, provenance));
  files.commit();
  folder.created = false;

  print_evaluation(out, model, mcm, e);
  for (const std::string& w : e.warnings) err << "gearmc: warning: " << w << "\n";
  out << "report: " << (folder.dir / "report.html").string() << "\n";
  return 0;
}

}  // namespace gearmc

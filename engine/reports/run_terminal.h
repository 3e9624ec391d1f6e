// What `gearmc run` prints and writes beside the report files, composed here so that the command
// line only handles arguments and prints: the header line of a run, the points.csv rows (one per
// probed point, docs/formats.md), the contacts line and the closing summary (mesh flanks, the
// result tables of run_report.h and the verdict on the flank-maximum law). Lengths in mm,
// errors in µm, as the columns say.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "engine/reports/run_report.h"
#include "engine/run/monte_carlo.h"

namespace gearmc {

// "gearmc run: NAME, G gears, T teeth, P points per flank, R r mm, seed S" (one gear with
// " (--only-gear K)" when `only_gear` is set); no line end.
std::string run_header_line(const Scenario& scenario, const MonteCarloRun& mc,
                            const std::optional<int>& only_gear);

// The column line of points.csv (after its provenance comment line), with its line end.
std::string points_csv_header();
// One row of points.csv for `p`: plan (gear, tooth, flank, i, j, p, n), then for a contact that
// gave a value the contact point C, the stylus centre O, the reported point E, delta_um,
// normal_err_um and "ok"; otherwise eleven empty fields and the reason (edge, the collision,
// the failure). Numbers with the stream's precision (run sets 17 significant digits).
void write_point_row(std::ostream& out, const ProbedPoint& p);

// "contacts N (failed F, edge E, collisions C) in T s" (wall time, 2 decimals); no line end.
std::string run_contacts_line(const RunResults& r);

// The terminal table of δRcomp statistics (and, with effects, the total error and its budget).
void print_run_tables(std::ostream& out, const Scenario& scenario, const RunResults& r,
                      const RunPresentation& view);

// The terminal summary after the contacts line and the warnings: each mesh flank, the result
// tables (print_run_tables) and the flank-maximum law of each side.
void print_run_summary(std::ostream& out, const Scenario& scenario, const RunResults& r,
                       const RunPresentation& view);

}  // namespace gearmc

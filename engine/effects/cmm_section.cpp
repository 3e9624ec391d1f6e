// The `cmm:` section read (cmm_effects.h): the data sheet's keys, the user's verification table,
// the rotary table's data sheet, the gear's place in the travel, and the machines (and tables)
// drawn and kept for them.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/input_file.h"
#include "core/number_text.h"
#include "core/text_lines.h"
#include "engine/effects/cmm_effects.h"
#include "engine/schema/parameter_ranges.h"
#include "engine/schema/scenario_keys.h"

namespace gearmc {
namespace {

Eigen::Vector3d read_vector(const YamlValue& value, const ParameterRange& range,
                            std::vector<std::string>* warnings) {
  const std::vector<YamlValue> items = value.as_sequence();
  if (items.size() != 3) {
    throw value.error("three numbers [x, y, z] in " + range.unit);
  }
  Eigen::Vector3d v;
  for (int a = 0; a < 3; ++a)
    v[a] = read_ranged(items[static_cast<std::size_t>(a)], range, warnings);
  return v;
}

std::string mm_text(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

}  // namespace

std::vector<VerificationRow> read_verification_table(const std::string& text,
                                                     const std::string& source,
                                                     const Eigen::Vector3d& travel_mm,
                                                     std::optional<double> default_u_um) {
  const std::vector<LengthTestPosition> positions = length_test_positions(travel_mm);
  std::string names;
  for (const LengthTestPosition& p : positions) names += (names.empty() ? "" : ", ") + p.name;
  TextLines lines(text, source, 4096, "a verification table");
  TextLine line;
  // The fields of a line with the column where each starts (1-based).
  const auto split = [](const std::string& t) {
    std::vector<std::pair<std::string, int>> out;
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = t.find(',', start);
      const std::size_t end = comma == std::string::npos ? t.size() : comma;
      std::size_t a = start, b = end;
      while (a < b && (t[a] == ' ' || t[a] == '\t')) ++a;
      while (b > a && (t[b - 1] == ' ' || t[b - 1] == '\t')) --b;
      out.emplace_back(t.substr(a, b - a), static_cast<int>(a) + 1);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return out;
  };
  int col_position = -1, col_length = -1, col_error = -1, col_u = -1;
  bool header = false;
  std::vector<VerificationRow> rows;
  const std::string header_text = "a header position,length_mm,error_um[,u_um]";
  while (lines.next(&line)) {
    const std::string& t = line.text;
    const std::size_t first = t.find_first_not_of(" \t");
    if (first == std::string::npos || t[first] == '#') continue;
    const auto fields = split(t);
    if (!header) {
      for (std::size_t c = 0; c < fields.size(); ++c) {
        const std::string& f = fields[c].first;
        int* slot = f == "position"    ? &col_position
                    : f == "length_mm" ? &col_length
                    : f == "error_um"  ? &col_error
                    : f == "u_um"      ? &col_u
                                       : nullptr;
        if (slot == nullptr || *slot >= 0) {
          throw InputError({source, line.number, fields[c].second}, "header", f,
                           slot ? header_text + ", each column once" : header_text);
        }
        *slot = static_cast<int>(c);
      }
      if (col_position < 0 || col_length < 0 || col_error < 0) {
        throw InputError({source, line.number, 1}, "header", t, header_text);
      }
      if (col_u < 0 && !default_u_um) {
        throw InputError({source, line.number, 1}, "header", t,
                         "a u_um column (the measured errors' standard uncertainty, µm), or "
                         "cmm.verification_u_um in the scenario");
      }
      header = true;
      continue;
    }
    const std::size_t needed =
        static_cast<std::size_t>(std::max({col_position, col_length, col_error, col_u})) + 1;
    if (fields.size() != needed) {
      throw InputError({source, line.number, 1}, "row", t,
                       std::to_string(needed) + " fields, as the header has");
    }
    const auto number = [&](int column, const char* key, double lo, double hi,
                            const std::string& expected) {
      const auto& [f, at] = fields[static_cast<std::size_t>(column)];
      char* end = nullptr;
      const double v = f.empty() ? 0.0 : std::strtod(f.c_str(), &end);
      if (f.empty() || end != f.c_str() + f.size() || !std::isfinite(v) || v < lo || v > hi) {
        throw InputError({source, line.number, at}, key, f, expected);
      }
      return v;
    };
    VerificationRow row;
    const auto& [name, name_at] = fields[static_cast<std::size_t>(col_position)];
    row.position = -1;
    for (std::size_t p = 0; p < positions.size(); ++p) {
      if (positions[p].name == name) row.position = static_cast<int>(p);
    }
    if (row.position < 0) {
      throw InputError({source, line.number, name_at}, "position", name,
                       "an ISO 10360-2 position: " + names);
    }
    const double line_mm = positions[static_cast<std::size_t>(row.position)].line_mm;
    row.length_mm = number(col_length, "length_mm", 1e-3, line_mm,
                           "a length > 0 within the " + name + " line through the travel (" +
                               shortest_text(line_mm) + " mm)");
    row.error_um =
        number(col_error, "error_um", -1000.0, 1000.0, "an error in µm from -1000 to 1000");
    row.u_um = col_u >= 0 ? number(col_u, "u_um", 1e-6, 100.0,
                                   "a standard uncertainty in µm > 0 and <= 100")
                          : *default_u_um;
    rows.push_back(row);
  }
  if (rows.empty()) {
    throw InputError({source, std::max(1, line.number), 1},
                     header ? source + ": no measured length error after the header"
                            : source + ": expected a verification table: " + header_text +
                                  ", then one row per measured length");
  }
  return rows;
}

std::shared_ptr<const CmmModel> read_cmm(const YamlValue& section, std::uint64_t seed,
                                         double gear_radius_mm, double face_width_mm,
                                         bool radial_shaft, bool internal,
                                         std::vector<std::string>* warnings) {
  const YamlMap map = section.as_map(child_keys("cmm"));
  const RangeTable& ranges = machine_ranges();
  auto model = std::make_shared<CmmModel>();
  model->seed = seed;
  model->face_width_mm = face_width_mm;
  model->where = section.key_location();
  if (const auto layout = map.get_choice("layout", key_choices("cmm.layout"))) {
    model->layout = parse_machine_layout(*layout);
  }
  // MPE_E, or a verification table instead of it (its absence then checked with the table).
  const std::optional<YamlValue> mpe = map.find("mpe_e_um");
  if (!mpe && !map.find("verification")) {
    throw map.missing("mpe_e_um", "MPE_E as \"A + L/K\" (µm, L in mm), or a verification table");
  }
  if (mpe) {
    model->mpe_e_text = mpe->as_string();
    try {
      model->mpe_e = parse_length_mpe(model->mpe_e_text);
    } catch (const std::invalid_argument&) {
      throw mpe->error(
          "MPE_E as \"A + L/K\" in µm with L in mm, A >= 0 and K > 0, e.g. \"1.8 + L/300\"");
    }
    // A and K each against their range, named by the key the user wrote.
    for (const auto& [number, part] : {std::pair{model->mpe_e.a_um, "cmm.mpe_e_um.A"},
                                       std::pair{model->mpe_e.k_mm_per_um, "cmm.mpe_e_um.K"}}) {
      ParameterRange range = ranges.at(part);
      range.key = mpe->path();
      check_ranged(number, range, mpe->location(), model->mpe_e_text, warnings);
    }
  }
  model->mpe_p_um = get_ranged(map, "mpe_p_um", ranges.at("cmm.mpe_p_um"), warnings);
  if (const auto travel = map.find("travel_mm")) {
    model->travel_mm = read_vector(*travel, ranges.at("cmm.travel_mm"), warnings);
  }
  if (const auto placement = map.find("placement_mm")) {
    model->placement_mm = read_vector(*placement, ranges.at("cmm.placement_mm"), warnings);
  }
  model->stylus_length_mm =
      get_ranged(map, "stylus_length_mm", ranges.at("cmm.stylus_length_mm"), warnings)
          .value_or(number_default("cmm.stylus_length_mm"));
  model->machines_wanted =
      static_cast<int>(get_ranged_int(map, "machines", ranges.at("cmm.machines"), warnings)
                           .value_or(static_cast<std::int64_t>(number_default("cmm.machines"))));
  model->order =
      static_cast<int>(get_ranged_int(map, "order", ranges.at("cmm.order"), warnings)
                           .value_or(static_cast<std::int64_t>(number_default("cmm.order"))));

  // The user's verification results (docs/cmm.md): read, and the prior conditioned on them.
  const std::optional<double> default_u =
      get_ranged(map, "verification_u_um", ranges.at("cmm.verification_u_um"), warnings);
  if (const auto table = map.find("verification")) {
    const std::string written = table->as_string();
    if (written.empty()) throw table->error("a verification table (a CSV file)");
    model->verification_written = written;
    const std::filesystem::path file(written);
    const std::filesystem::path folder = std::filesystem::path(section.file()).parent_path();
    model->verification_path =
        file.is_absolute() || folder.empty() ? file.string() : (folder / file).string();
    if (const auto why =
            unreadable_input_reason(model->verification_path, "verification table", 16u << 20)) {
      throw table->error("a readable verification table (" + *why + ")");
    }
    const std::string text =
        read_input_file(model->verification_path, "verification table", 16u << 20);
    model->verification =
        read_verification_table(text, model->verification_path, model->travel_mm, default_u);
  } else if (default_u) {
    throw map.find("verification_u_um")
        ->error("no value without `verification:` (it is that table's u)");
  }

  if (const auto table = map.get_map("rotary_table", child_keys("cmm.rotary_table"))) {
    RotaryTableSpec spec;
    spec.radial_um =
        get_ranged(*table, "radial_um", ranges.at("cmm.rotary_table.radial_um"), warnings)
            .value_or(0.0);
    spec.axial_um = get_ranged(*table, "axial_um", ranges.at("cmm.rotary_table.axial_um"), warnings)
                        .value_or(0.0);
    spec.angular_arcsec =
        get_ranged(*table, "angular_arcsec", ranges.at("cmm.rotary_table.angular_arcsec"), warnings)
            .value_or(0.0);
    model->table = spec;
  }

  // The gear must lie inside the travel: outside it the error functions (Legendre series over
  // the travel) would be extrapolated.
  {
    const double l = model->stylus_length_mm;
    Eigen::Vector3d reach, low;  // the axes' positions' extremes over the gear's ball centres
    if (!radial_shaft) {
      reach << gear_radius_mm, gear_radius_mm, face_width_mm + l;
      low << -gear_radius_mm, -gear_radius_mm, l;
    } else {
      // The ram outside an external gear, inside a ring gear (towards its axis).
      const double r = internal ? gear_radius_mm : gear_radius_mm + l;
      reach << r, r, face_width_mm;
      low << -r, -r, 0.0;
    }
    for (int a = 0; a < 3; ++a) {
      const double hi = reach[a] + model->placement_mm[a];
      const double lo = low[a] + model->placement_mm[a];
      const double half = 0.5 * model->travel_mm[a];
      if (hi > half || lo < -half) {
        const auto where =
            map.find("placement_mm") ? map.find("placement_mm") : map.find("travel_mm");
        const std::string axis(1, "xyz"[a]);
        const std::string expected =
            "a placement that keeps the gear inside the travel: its ram positions reach " + axis +
            " = " + mm_text(lo) + " … " + mm_text(hi) + " mm, the travel is ±" + mm_text(half) +
            " mm (gear radius " + mm_text(gear_radius_mm) + " mm, stylus " + mm_text(l) + " mm)";
        if (where) throw where->error(expected);
        throw map.missing("travel_mm", expected);
      }
    }
  }

  LengthTestOptions test;
  test.stylus_mm = Eigen::Vector3d(0.0, 0.0, -model->stylus_length_mm);
  const ProbePrior probe = model->mpe_p_um ? probe_prior_for(*model->mpe_p_um) : ProbePrior{};
  if (!mpe) {
    model->mpe_from_table = true;
    model->mpe_e = prior_scales_from_table(model->layout, model->travel_mm, model->order, probe,
                                           model->verification, test);
    // At the grid's wide end the table asks for larger errors than the prior can give: say so.
    if (warnings != nullptr &&
        (model->mpe_e.a_um > 0.999 * 30.0 || model->mpe_e.k_mm_per_um < 1.001 * 30.0)) {
      warnings->push_back(
          InputError(map.find("verification")->location(),
                     "cmm.verification: the table's errors reach the widest prior scales gearmc "
                     "tries (A 30 µm or K 30 mm/µm): the machines drawn may be better than the "
                     "table says — give the machine's MPE_E (cmm.mpe_e_um)")
              .what());
    }
  }
  const MachinePrior prior = [&] {
    MachinePrior p = prior_for(model->mpe_e, model->layout, model->travel_mm);
    p.order = model->order;
    return p;
  }();
  // Without a data sheet there is no MPE_E to pass (the table is the constraint).
  const LengthMpe limit =
      mpe ? model->mpe_e : LengthMpe{std::numeric_limits<double>::infinity(), 1.0};
  // An acceptance rate below 1 % is refused: the prior would then say more than the data sheet.
  const int max_draws = std::max(2000, 100 * model->machines_wanted);
  if (!model->verification.empty()) {
    model->posterior = std::make_shared<const MachinePosterior>(
        verification_posterior(prior, probe, model->verification, test));
    if (model->posterior->p_value < 1e-3 && warnings != nullptr) {
      std::ostringstream w;
      w.precision(3);
      w << "the measured length errors are unlike those of the prior's machines (χ² = "
        << model->posterior->chi_square << " for " << model->verification.size()
        << " rows, p = " << model->posterior->p_value
        << "): the machines follow them only as far as the prior lets them — check the table's "
           "sign (measured − calibrated length), its units (µm) and u_um";
      warnings->push_back(
          InputError(map.find("verification")->location(), "cmm.verification: " + w.str()).what());
    }
  }
  model->kept = draw_constrained(prior, limit, model->machines_wanted, max_draws, seed, test, probe,
                                 0.01, model->posterior.get());
  if (model->kept.refused) {
    const YamlValue& at = mpe ? *mpe : *map.find("verification");
    throw InputError(at.location(), at.path(), at.as_string(),
                     "a data sheet the machine prior can meet; " + model->kept.why);
  }
  if (model->table) {
    // One kept table per kept machine (their own draws, index by index; a perfect data sheet
    // value keeps that motion at zero).
    for (std::uint64_t i = 0; model->tables.size() < model->kept.kept.size(); ++i) {
      if (i >= static_cast<std::uint64_t>(max_draws)) {
        throw map.find("rotary_table")
            ->error("a table data sheet the prior can meet (" +
                    std::to_string(model->tables.size()) + " of " + std::to_string(i) +
                    " drawn tables passed)");
      }
      ++model->tables_drawn;
      const RotaryTableErrors t = draw_rotary_table(*model->table, seed, i);
      if (meets(t, *model->table)) model->tables.push_back(t);
    }
  }
  // The length test does not depend on where the gear stands; the gear's points do.
  for (KinematicMachine& m : model->kept.kept) m.placement_mm = model->placement_mm;
  return model;
}

}  // namespace gearmc

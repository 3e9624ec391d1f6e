// Grid of scenario variants, their runs over the ranks, and the sweep statistic (sweep.h).
#include "engine/apps/sweep/sweep.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "core/bytes.h"
#include "core/input_error.h"
#include "engine/apps/sweep/sweep_bands.h"
#include "engine/run/run_partials.h"
#include "engine/schema/scenario_keys.h"
#include "engine/statistics/stats_json.h"
#include "gears/tolerances.h"

namespace gearmc {
namespace {

const std::vector<std::string> kQuantities = {"point", "flank_max", "flank_mean"};
const std::vector<std::string> kStatistics = {"n", "mean", "std", "min", "max", "p95", "p99_73"};

std::vector<std::string> split(const std::string& text, char by) {
  std::vector<std::string> parts;
  std::size_t at = 0;
  for (;;) {
    const std::size_t next = text.find(by, at);
    parts.push_back(text.substr(at, next - at));
    if (next == std::string::npos) return parts;
    at = next + 1;
  }
}

// Sets the dotted `key` of `root` to the YAML value `value`, creating maps on the way.
void set_key(YAML::Node root, const std::string& key, const std::string& value) {
  const std::vector<std::string> parts = split(key, '.');
  YAML::Node node = root;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    if (node[parts[i]] && !node[parts[i]].IsMap()) {
      throw InputError({}, "--vary", key,
                       "a key inside a section ('" + parts[i] + "' is not a section)");
    }
    if (!node[parts[i]]) node[parts[i]] = YAML::Node(YAML::NodeType::Map);
    node.reset(node[parts[i]]);
  }
  node[parts.back()] = YAML::Load(value);
}

// The part of an InputError's message after its "file:line:col: " (the line is that of the
// variant's generated text, not of the user's file).
std::string without_location(const InputError& e) {
  const std::string what = e.what();
  const InputLocation& w = e.where();
  if (w.file.empty() || what.rfind(w.file, 0) != 0) return what;
  std::size_t at = w.file.size();
  while (at < what.size() &&
         (what[at] == ':' || std::isdigit(static_cast<unsigned char>(what[at])))) {
    ++at;
  }
  while (at < what.size() && what[at] == ' ') ++at;
  return what.substr(at);
}

}  // namespace

SweepAxis parse_vary(const std::string& text) {
  const std::size_t eq = text.find('=');
  const std::string expected =
      "KEY=V1,V2,… (a scenario key such as stylus.radius_mm and its values)";
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw InputError({}, "--vary", text, expected);
  }
  SweepAxis axis{text.substr(0, eq), split(text.substr(eq + 1), ',')};
  for (const std::string& part : split(axis.key, '.')) {
    if (part.empty()) throw InputError({}, "--vary", text, expected);
  }
  for (std::size_t i = 0; i < axis.values.size(); ++i) {
    if (axis.values[i].empty())
      throw InputError({}, "--vary", text, expected + "; a value is empty");
    for (std::size_t k = 0; k < i; ++k) {
      if (axis.values[k] == axis.values[i]) {
        throw InputError({}, "--vary", text, "values that differ ('" + axis.values[i] + "' twice)");
      }
    }
  }
  return axis;
}

namespace {
const std::vector<std::string> kParameterStatistics = {
    "bias", "u", "U", "U_over_T", "Q_MP", "false_accept", "false_reject"};
}  // namespace

bool SweepStatistic::ratio() const {
  return !parameter.empty() && statistic != "bias" && statistic != "u" && statistic != "U";
}

SweepStatistic parse_sweep_statistic(const std::string& text) {
  const std::vector<std::string> parts = split(text, '.');
  const std::string expected =
      "delta_rcomp.<point|flank_max|flank_mean>.<n|mean|std|min|max|p95|p99_73> or "
      "parameters.<symbol>.<bias|u|U|U_over_T|Q_MP|false_accept|false_reject>";
  if (parts.size() == 3 && parts[0] == "parameters") {
    const std::vector<std::string>& symbols = scenario_key("evaluation.parameters").allowed;
    if (std::find(symbols.begin(), symbols.end(), parts[1]) == symbols.end()) {
      throw InputError({}, "--statistic", text, expected, did_you_mean(parts[1], symbols));
    }
    if (std::find(kParameterStatistics.begin(), kParameterStatistics.end(), parts[2]) ==
        kParameterStatistics.end()) {
      throw InputError({}, "--statistic", text, expected,
                       did_you_mean(parts[2], kParameterStatistics));
    }
    return {text, "parameters", parts[2], parts[1]};
  }
  if (parts.size() != 3 || parts[0] != "delta_rcomp") {
    throw InputError({}, "--statistic", text, expected);
  }
  if (std::find(kQuantities.begin(), kQuantities.end(), parts[1]) == kQuantities.end()) {
    throw InputError({}, "--statistic", text, expected, did_you_mean(parts[1], kQuantities));
  }
  if (std::find(kStatistics.begin(), kStatistics.end(), parts[2]) == kStatistics.end()) {
    throw InputError({}, "--statistic", text, expected, did_you_mean(parts[2], kStatistics));
  }
  return {text, parts[1], parts[2], ""};
}

void check_sweep_statistic(const SweepStatistic& s, const std::vector<SweepPoint>& points) {
  if (s.parameter.empty()) return;
  for (const SweepPoint& p : points) {
    const auto& e = p.scenario.evaluation;
    if (e &&
        std::find(e->parameters.begin(), e->parameters.end(), s.parameter) != e->parameters.end()) {
      continue;
    }
    std::string at;
    for (const std::string& v : p.values) at += (at.empty() ? "" : ", ") + v;
    throw InputError({}, "--statistic", s.text,
                     "a parameter every variant evaluates: " +
                         (e ? "evaluation.parameters has no " + s.parameter
                            : std::string("the scenario has no evaluation: section")) +
                         (points.size() > 1 ? " (variant " + at + ")" : std::string()));
  }
}

std::string sweep_runs_text(const std::vector<SweepPoint>& points, bool brief) {
  if (points.empty()) return "no gears";
  int gears_lo = points[0].scenario.gears, gears_hi = gears_lo;
  std::uint64_t seed_lo = points[0].scenario.seed, seed_hi = seed_lo;
  for (const SweepPoint& p : points) {
    gears_lo = std::min(gears_lo, p.scenario.gears);
    gears_hi = std::max(gears_hi, p.scenario.gears);
    seed_lo = std::min(seed_lo, p.scenario.seed);
    seed_hi = std::max(seed_hi, p.scenario.seed);
  }
  if (brief) {
    return (gears_lo == gears_hi ? std::to_string(gears_lo)
                                 : std::to_string(gears_lo) + "–" + std::to_string(gears_hi)) +
           " gears";
  }
  std::string text = gears_lo == gears_hi
                         ? std::to_string(gears_lo) + " gears each"
                         : std::to_string(gears_lo) + "–" + std::to_string(gears_hi) + " gears";
  if (seed_lo == seed_hi) {
    text += " (seed " + std::to_string(seed_lo) + ", the same perturbed gears at every point" +
            (gears_lo == gears_hi ? ")" : ", the first gears of the larger runs)");
  } else {
    text += " (seeds " + std::to_string(seed_lo) + "–" + std::to_string(seed_hi) +
            ": other perturbed gears for each seed)";
  }
  return text;
}

ErrorStatistics sweep_quantity(const SweepStatistic& s, const RunResults& r, int side) {
  const auto pick = [&](int k) -> const ErrorStatistics& {
    if (s.quantity == "point") return r.point[k];
    if (s.quantity == "flank_max") return r.flank_max[k];
    return r.flank_mean[k];
  };
  if (side < 2) return pick(side);
  ErrorStatistics both = pick(0);
  both.merge(pick(1));
  return both;
}

std::optional<double> sweep_statistic_value(const SweepStatistic& s, const ErrorStatistics& v,
                                            std::string* note) {
  const std::uint64_t n = v.moments.count();
  if (s.statistic == "n") return static_cast<double>(n);
  const auto none = [&](const std::string& why) -> std::optional<double> {
    if (note) *note = why;
    return std::nullopt;
  };
  if (n == 0) return none("no values");
  if (s.statistic == "mean") return v.moments.mean();
  if (s.statistic == "min") return v.moments.min();
  if (s.statistic == "max") return v.moments.max();
  if (s.statistic == "std") {
    if (n < 2) return none("not enough values: n = 1, std needs at least 2");
    return v.moments.stddev();
  }
  const double p = s.statistic == "p95" ? 0.95 : 0.9973;
  const std::optional<double> q = supported_quantile(v.histogram, p);
  if (!q) return none(not_enough_values_note(n, p));
  return q;
}

std::vector<SweepPoint> sweep_grid(const std::string& base_text, const std::string& base_path,
                                   const std::vector<SweepAxis>& axes,
                                   const ScenarioOverrides& overrides) {
  // A key that the command line also sets would be silently overridden in every variant.
  for (const SweepAxis& a : axes) {
    if (overrides.gears && (a.key == "run.gears" || a.key == "run")) {
      throw InputError({}, "--vary", a.key,
                       "a key --gears does not override (both set the gear count: give one)");
    }
    if (overrides.seed && a.key == "seed") {
      throw InputError({}, "--vary", a.key,
                       "a key --seed does not override (both set the seed: give one)");
    }
  }
  std::size_t total = 1;
  for (const SweepAxis& a : axes) total *= a.values.size();
  std::vector<SweepPoint> points;
  for (std::size_t index = 0; index < total; ++index) {
    SweepPoint point;
    point.values.resize(axes.size());
    std::size_t rest = index;
    for (std::size_t a = axes.size(); a-- > 0;) {
      point.values[a] = axes[a].values[rest % axes[a].values.size()];
      rest /= axes[a].values.size();
    }
    std::string label;
    for (std::size_t a = 0; a < axes.size(); ++a) {
      label += (a ? " " : "") + std::string("--vary ") + axes[a].key + "=" + point.values[a];
    }
    try {
      YAML::Node root = YAML::Load(base_text);
      for (std::size_t a = 0; a < axes.size(); ++a) set_key(root, axes[a].key, point.values[a]);
      YAML::Emitter text;
      text << root;
      point.scenario = parse_scenario(std::string(text.c_str()) + "\n", base_path);
    } catch (const InputError& e) {
      throw InputError({}, base_path + " with " + label + ": " + without_location(e));
    } catch (const YAML::Exception& e) {
      throw InputError({}, base_path + " with " + label + ": not a YAML value: " + e.what());
    }
    apply_overrides(overrides, point.scenario);
    points.push_back(std::move(point));
  }
  return points;
}

std::vector<RunResults> run_sweep(const std::vector<SweepPoint>& points, int threads,
                                  const Ranks& ranks, const std::function<void(int, int)>& progress,
                                  const SweepStatistic* s, std::vector<GearValues>* gear_values) {
  const int total = static_cast<int>(points.size());
  const Ranks::Share mine = ranks.share(points.size());
  const bool per_gear = gear_values != nullptr && s != nullptr && s->parameter.empty();
  std::vector<RunResults> local;
  std::vector<GearValues> local_gears;
  const std::vector<std::string> parts = ranks.gather([&] {
    std::string bytes;
    for (std::uint64_t i = mine.begin; i < mine.end; ++i) {
      const Scenario& scenario = points[i].scenario;
      const MonteCarloRun mc(scenario);
      RunOptions options;
      options.threads = threads;
      GearValues gears;
      if (per_gear) {
        options.on_gear = [&](const GearOutcome& g) {
          const auto& q = s->quantity == "point"       ? g.point_delta
                          : s->quantity == "flank_max" ? g.flank_max
                                                       : g.flank_mean;
          gears.add_gear(q[0], q[1]);
        };
      }
      RunResults r;
      try {
        r = mc.run(options);
      } catch (const ToleranceError& e) {
        throw InputError({}, scenario.source_path + ": tolerances: " + e.what());
      }
      if (ranks.is_root()) {
        local.push_back(std::move(r));
        local_gears.push_back(std::move(gears));
        if (progress) {
          progress(std::min(total, static_cast<int>(local.size()) * ranks.size()), total);
        }
      } else {
        ByteWriter(bytes).put_text(encode_partial(r));
        std::string encoded;
        gears.encode(encoded);
        ByteWriter(bytes).put_text(encoded);
      }
    }
    return bytes;
  });
  if (!ranks.is_root()) return {};
  for (std::size_t r = 1; r < parts.size(); ++r) {
    ByteReader in(parts[r]);
    while (!in.done()) {
      local.push_back(decode_partial(in.get_text()));
      local_gears.push_back(GearValues::decode(in.get_text()));
    }
  }
  if (per_gear) *gear_values = std::move(local_gears);
  return local;
}

}  // namespace gearmc

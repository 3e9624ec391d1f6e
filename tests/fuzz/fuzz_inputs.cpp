// A bounded, deterministic mutation fuzzer of gearmc's input readers, run as a ctest test.
// Every seed file of tests/fuzz/corpus/scenario (scenarios/ plus edge cases),
// tests/fuzz/corpus/model (uncertainty model files), tests/fuzz/corpus/readings and
// tests/fuzz/corpus/verification (a CMM's verification tables, cmm.verification) is mutated from
// a fixed seed (byte flips, special values such as 1e308, nan, -1, "", very long tokens, non-UTF-8
// bytes, deleted, duplicated and swapped lines, truncation, deep nesting) and each mutant is fed
// in-process to the scenario reader (load, which resolves and checks the tolerances, then the gear
// geometry and one drawn gear, the work `gearmc geometry` and the start of `gearmc run` do), to the
// uncertainty model reader (then the GUM and, when at most 20 000 trials give an interval, a short
// Monte-Carlo run), to the readings reader or to the verification table reader. The test fails when
// anything other than success or an InputError escapes (another exception; a crash ends the
// process, which ctest reports as a failure), and when an InputError's message is not one clean
// line of bounded length. It stops after --mutants mutants or --seconds seconds, whichever comes
// first, and prints how many mutants ran, were accepted and rejected cleanly.
//
//   fuzz_inputs --corpus DIR [--mutants N] [--seconds S] [--seed K] [--save-failures DIR]
//               [--trace 1]
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/input_file.h"
#include "engine/apps/uncertainty/gum.h"
#include "engine/apps/uncertainty/mcm.h"
#include "engine/apps/uncertainty/model.h"
#include "engine/effects/cmm_effects.h"
#include "engine/readings/readings_csv.h"
#include "engine/scenario/scenario.h"
#include "gears/deviations.h"
#include "gears/involute_gear.h"
#include "gears/tolerances.h"

namespace {

using gearmc::InputError;
using namespace std::string_literals;

// Values that have broken parsers before or are at the edges of every number type.
const std::vector<std::string> kSpecialTokens = {"1e308",
                                                 "-1e308",
                                                 "1e309",
                                                 "1e-320",
                                                 "nan",
                                                 ".nan",
                                                 "NaN",
                                                 "inf",
                                                 ".inf",
                                                 "-.inf",
                                                 "-1",
                                                 "0",
                                                 "-0",
                                                 "0x10",
                                                 "1_000",
                                                 "99999999999999999999",
                                                 "-9223372036854775809",
                                                 "2147483648",
                                                 "\"\"",
                                                 "''",
                                                 "~",
                                                 "null",
                                                 "[]",
                                                 "{}",
                                                 "[1, 2]",
                                                 "{a: 1}",
                                                 "true",
                                                 "1e300",
                                                 "0.349",
                                                 "0.02",
                                                 "300",
                                                 "\xff\xfe",
                                                 "\xc3\x28",
                                                 "\xed\xa0\x80",
                                                 "\xf4\x90\x80\x80",
                                                 "\x01",
                                                 "\t",
                                                 "\r",
                                                 "&a",
                                                 "*a",
                                                 "!!binary",
                                                 "? x",
                                                 ": ",
                                                 "- ",
                                                 "#",
                                                 "\"\\u0000\"",
                                                 "!!str 5",
                                                 "<<: {}",
                                                 "%YAML 1.2",
                                                 "---",
                                                 "...",
                                                 ",",
                                                 "L",
                                                 "R",
                                                 "\xc2\xa0"};

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = text.find('\n', start);
    if (end == std::string::npos) {
      if (start < text.size()) lines.push_back(text.substr(start));
      break;
    }
    lines.push_back(text.substr(start, end - start + 1));
    start = end + 1;
  }
  return lines;
}

std::string join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& l : lines) text += l;
  return text;
}

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::string mutate(std::string text) {
    const int rounds = 1 + static_cast<int>(below(3));
    for (int r = 0; r < rounds; ++r) text = once(std::move(text));
    return text;
  }

 private:
  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng_() % n); }
  const std::string& special() { return kSpecialTokens[below(kSpecialTokens.size())]; }

  // The start and length of a number in the text (a digit run with sign, dot, exponent), if any.
  bool find_number(const std::string& text, std::size_t* start, std::size_t* length) {
    for (int tries = 0; tries < 8; ++tries) {
      std::size_t i = below(text.size());
      while (i < text.size() && !(text[i] >= '0' && text[i] <= '9')) ++i;
      if (i >= text.size()) continue;
      std::size_t b = i;
      while (b > 0 && (std::isdigit(static_cast<unsigned char>(text[b - 1])) ||
                       text[b - 1] == '.' || text[b - 1] == '-'))
        --b;
      std::size_t e = i;
      while (e < text.size() && (std::isdigit(static_cast<unsigned char>(text[e])) ||
                                 text[e] == '.' || text[e] == 'e' || text[e] == '-'))
        ++e;
      *start = b;
      *length = e - b;
      return true;
    }
    return false;
  }

  std::string once(std::string text) {
    if (text.empty()) return special();
    std::vector<std::string> lines;
    std::size_t a = 0, n = 0;
    switch (below(12)) {
      case 0:  // flip one byte
        text[below(text.size())] = static_cast<char>(below(256));
        return text;
      case 1:  // insert a special token at a random place
        return text.insert(below(text.size() + 1), special());
      case 2:  // replace a number with a special token
      case 3:
        if (find_number(text, &a, &n)) return text.replace(a, n, special());
        return text.insert(below(text.size() + 1), special());
      case 4:  // delete a line
        lines = lines_of(text);
        if (!lines.empty()) lines.erase(lines.begin() + static_cast<long>(below(lines.size())));
        return join(lines);
      case 5:  // duplicate a line (duplicate keys, repeated rows)
        lines = lines_of(text);
        if (!lines.empty()) {
          const std::size_t k = below(lines.size());
          lines.insert(lines.begin() + static_cast<long>(k), lines[k]);
        }
        return join(lines);
      case 6:  // swap two lines
        lines = lines_of(text);
        if (lines.size() > 1) std::swap(lines[below(lines.size())], lines[below(lines.size())]);
        return join(lines);
      case 7:  // truncate
        text.resize(below(text.size() + 1));
        return text;
      case 8:  // a very long token
        return text.insert(below(text.size() + 1),
                           std::string(1000 + below(20000), "a9[{\"-,"[below(7)]));
      case 9:  // non-UTF-8 bytes or control characters
        return text.insert(
            below(text.size() + 1),
            std::string(1, static_cast<char>(0x80 + below(128))) + (below(2) ? "\x00"s : "\x1b"s));
      case 10:  // deep nesting
        return text.insert(below(text.size() + 1), std::string(1 + below(5000), "[{"[below(2)]));
      default:  // line ends: LF -> CR or CRLF
        for (char& c : text) {
          if (c == '\n' && below(4) == 0) c = '\r';
        }
        return text;
    }
  }

  std::mt19937_64 rng_;
};

// A clean message: one line (no control characters at all) and bounded (a few hundred
// characters of our text around at most a few 60-character echoes).
bool clean_message(const std::string& message, std::string* why) {
  for (const char c : message) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) {
      *why = "a control character in the message";
      return false;
    }
  }
  if (gearmc::first_invalid_utf8(message)) {
    *why = "bytes that are not UTF-8 in the message";
    return false;
  }
  if (message.size() > 4000) {
    *why = "a message of " + std::to_string(message.size()) + " bytes";
    return false;
  }
  return true;
}

// The work `gearmc geometry` does on a loaded scenario, and the first gear of `run`.
void use_scenario(const gearmc::Scenario& s) {
  const gearmc::InvoluteGear gear(s.gear);
  const gearmc::ToleranceSet set = gearmc::resolve_tolerances(s.tolerances, gear);
  (void)gearmc::evaluation_ranges(gear);
  const gearmc::GearSampler sampler(gear, set, s.deviations, s.seed);
  (void)sampler.draw(0);
}

// The GUM of a loaded model and, when it is short, the Monte-Carlo run of `gearmc uncertainty`
// (its trial count checked as the command checks it).
void use_model(const gearmc::uncertainty::UncertaintyModel& m) {
  using namespace gearmc::uncertainty;
  (void)evaluate_gum(m);
  const double p = m.settings.coverage_probability;
  const double need = 1.0 / (1.0 - p) + 2.0;
  if (need > 20000.0) return;
  McmOptions o;
  o.trials = static_cast<std::uint64_t>(std::max(200.0, need));
  o.coverage_probability = p;
  o.seed = m.settings.seed;
  o.threads = 1;
  check_trials(*o.trials, m.outputs.size(), p, {}, "trials");
  (void)run_mcm(m, o);
}

}  // namespace

// A verification table read as `cmm.verification` reads it (the example bridge's travel, a
// default u so that a table without the column is valid).
void read_verification(const std::string& text, const std::string& name) {
  gearmc::read_verification_table(text, name, Eigen::Vector3d(700.0, 1000.0, 600.0), 0.2);
}

int main(int argc, char** argv) {
  std::filesystem::path corpus;
  long long max_mutants = 4000;
  double max_seconds = 20.0;
  std::uint64_t seed = 20261122;
  std::filesystem::path save_dir;
  bool trace = false;  // print each mutant's name before reading it (to find a hang)
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--corpus")
      corpus = argv[i + 1];
    else if (flag == "--mutants")
      max_mutants = std::stoll(argv[i + 1]);
    else if (flag == "--seconds")
      max_seconds = std::stod(argv[i + 1]);
    else if (flag == "--seed")
      seed = std::stoull(argv[i + 1]);
    else if (flag == "--save-failures")
      save_dir = argv[i + 1];
    else if (flag == "--trace")
      trace = std::string(argv[i + 1]) == "1";
    else {
      std::cerr << "unknown option " << flag << "\n";
      return 2;
    }
  }
  struct Seed {
    std::string name, text;
    bool readings;
    bool model = false;
    bool verification = false;  // a CMM's verification table (cmm.verification)
  };
  std::vector<Seed> seeds;
  for (const char* kind : {"scenario", "readings", "model", "verification"}) {
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(corpus / kind)) {
      files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());  // a fixed order: the run is deterministic
    for (const auto& f : files) {
      seeds.push_back({f.filename().string(), read_text(f), std::string(kind) == "readings",
                       std::string(kind) == "model", std::string(kind) == "verification"});
    }
  }
  if (seeds.empty()) {
    std::cerr << "fuzz_inputs: no seed files under " << corpus << "\n";
    return 1;
  }

  // Every seed itself must be accepted (else the mutants test nothing near valid input).
  int failures = 0;
  for (const Seed& s : seeds) {
    try {
      if (s.verification) {
        read_verification(s.text, s.name);
      } else if (s.model) {
        use_model(gearmc::uncertainty::parse_uncertainty_model(s.text, s.name));
      } else if (s.readings) {
        gearmc::parse_readings(s.text, s.name);
      } else {
        use_scenario(gearmc::parse_scenario(s.text, s.name));
      }
    } catch (const std::exception& e) {
      std::cerr << "seed " << s.name << " is not accepted: " << e.what() << "\n";
      ++failures;
    }
  }

  Mutator mutator(seed);
  const auto start = std::chrono::steady_clock::now();
  long long ran = 0, accepted = 0, rejected = 0;
  bool out_of_time = false;
  for (; ran < max_mutants; ++ran) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > max_seconds) {
      out_of_time = true;
      break;
    }
    const Seed& s = seeds[static_cast<std::size_t>(ran) % seeds.size()];
    const std::string mutant = mutator.mutate(s.text);
    const std::string name = "mutant-" + std::to_string(ran) + "-" + s.name;
    std::string problem;
    if (trace) {
      std::cerr << name << std::endl;
      if (!save_dir.empty()) {
        std::filesystem::create_directories(save_dir);
        std::ofstream(save_dir / "current", std::ios::binary) << mutant;
      }
    }
    try {
      if (s.verification) {
        read_verification(mutant, name);
      } else if (s.model) {
        use_model(gearmc::uncertainty::parse_uncertainty_model(mutant, name));
      } else if (s.readings) {
        gearmc::parse_readings(mutant, name);
      } else {
        use_scenario(gearmc::parse_scenario(mutant, name));
      }
      ++accepted;
    } catch (const InputError& e) {
      std::string why;
      if (clean_message(e.what(), &why)) {
        ++rejected;
      } else {
        problem = "InputError with " + why + ": " + gearmc::shown_input(e.what(), 300);
      }
    } catch (const std::exception& e) {
      problem = "not an InputError: " + gearmc::shown_input(e.what(), 300);
    }
    if (!problem.empty()) {
      ++failures;
      std::cerr << name << ": " << problem << "\n";
      if (!save_dir.empty()) {
        std::filesystem::create_directories(save_dir);
        std::ofstream(save_dir / name, std::ios::binary) << mutant;
      }
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "fuzz_inputs: " << seeds.size() << " seeds, " << ran << " mutants in " << seconds
            << " s (seed " << seed << (out_of_time ? ", stopped at the time limit" : "")
            << "): " << accepted << " accepted, " << rejected << " rejected with an InputError, "
            << failures << " failures\n";
  return failures == 0 ? 0 : 1;
}

// Units of uncertainty models (engine/apps/uncertainty/units.h): units parse to the SI scale and
// base dimensions of the SI Brochure (9th ed., tables 2–5 and 7: N = kg m s⁻², Pa = N/m²,
// J = N m, L = dm³, µ = 10⁻⁶); the model check accepts JCGM 101 §9.3's mass calibration in its own
// units (mg and kg/m³) and refuses, at the output with what it found, the plausible slips: a
// prefix mixed into a sum (g for mg), a sum of unlike quantities, a constant without its unit,
// a disagreement hidden at the estimates by a vanishing factor, a missing or unknown unit.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "core/input_error.h"
#include "engine/apps/uncertainty/model.h"
#include "engine/apps/uncertainty/units.h"

namespace gearmc::uncertainty {
namespace {

void expect_unit(const std::string& text, double scale, std::array<double, 7> exponent) {
  const Unit u = parse_unit(text);
  EXPECT_NEAR(u.scale, scale, 1e-12 * scale) << text;
  for (std::size_t d = 0; d < 7; ++d)
    EXPECT_DOUBLE_EQ(u.exponent[d], exponent[d]) << text << " " << d;
}

TEST(UncertaintyUnits, UnitsParseToTheirSiScaleAndDimension) {
  expect_unit("m", 1, {1, 0, 0, 0, 0, 0, 0});
  expect_unit("mm", 1e-3, {1, 0, 0, 0, 0, 0, 0});
  expect_unit("um", 1e-6, {1, 0, 0, 0, 0, 0, 0});
  expect_unit("\u00b5m", 1e-6, {1, 0, 0, 0, 0, 0, 0});
  expect_unit("mg", 1e-6, {0, 1, 0, 0, 0, 0, 0});
  expect_unit("kg/m^3", 1, {-3, 1, 0, 0, 0, 0, 0});
  expect_unit("g/cm^3", 1e3, {-3, 1, 0, 0, 0, 0, 0});
  expect_unit("N*m", 1, {2, 1, -2, 0, 0, 0, 0});  // = J
  expect_unit("J", 1, {2, 1, -2, 0, 0, 0, 0});
  expect_unit("kPa", 1e3, {-1, 1, -2, 0, 0, 0, 0});
  expect_unit("um/m K", 1e-6, {0, 0, 0, 0, -1, 0, 0});  // what follows '/' is the denominator
  expect_unit("m s^-2", 1, {1, 0, -2, 0, 0, 0, 0});
  expect_unit("L", 1e-3, {3, 0, 0, 0, 0, 0, 0});
  expect_unit("min", 60, {0, 0, 1, 0, 0, 0, 0});
  expect_unit("Hz^0.5", 1, {0, 0, -0.5, 0, 0, 0, 0});
  expect_unit("1", 1, {});
  expect_unit("deg", 1, {});  // a pure number of scale 1 (units.h)
  EXPECT_EQ(dimension_text(parse_unit("kg/m^3")), "m^-3 kg");
  EXPECT_EQ(dimension_text(parse_unit("rad")), "1");
  for (const char* bad : {"", "furlong", "m^", "m^0", "m/s/s", "km^x"}) {
    EXPECT_THROW(parse_unit(bad), std::invalid_argument) << bad;
  }
}

// JCGM 101 §9.3's mass calibration with units; `replace` swaps one piece of its text.
std::string mass_model(const std::string& from = "", const std::string& to = "") {
  std::string text = R"M(name: mass
inputs:
  m_Rc:  {normal: [100000.000, 0.050]}
  dm_Rc: {normal: [1.234, 0.020]}
  rho_a: {uniform: [1.10, 1.30]}
  rho_W: {uniform: [7000, 9000]}
  rho_R: {uniform: [7950, 8050]}
constants: {m_nom: 100000, rho_a0: 1.2}
outputs:
  dm: "(m_Rc + dm_Rc)*(1 + (rho_a - rho_a0)*(1/rho_W - 1/rho_R)) - m_nom"
units: {m_Rc: mg, dm_Rc: mg, rho_a: kg/m^3, rho_W: kg/m^3, rho_R: kg/m^3, m_nom: mg,
        rho_a0: kg/m^3, dm: mg}
)M";
  if (!from.empty()) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  return text;
}

std::string error_of(const std::string& text) {
  try {
    parse_uncertainty_model(text, "m.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(UncertaintyUnits, TheMassCalibrationAgreesWithItsUnits) {
  const UncertaintyModel m = parse_uncertainty_model(mass_model(), "m.yaml");
  ASSERT_EQ(m.units.size(), 8u);
  EXPECT_EQ(m.units.at("rho_W").text, "kg/m^3");
  // Everything in g instead of mg agrees too (one scale for every mass).
  std::string grams = mass_model();
  for (std::size_t at; (at = grams.find(": mg")) != std::string::npos;) grams.replace(at, 4, ": g");
  EXPECT_EQ(error_of(grams), "no error");
}

TEST(UncertaintyUnits, SlipsAreRefusedAtTheOutputWithWhatWasFound) {
  // dm_Rc stated in g while the sum adds it to milligrams: the scales disagree.
  const std::string prefix = error_of(mass_model("dm_Rc: mg", "dm_Rc: g"));
  EXPECT_NE(prefix.find("m.yaml:10:"), std::string::npos) << prefix;
  EXPECT_NE(prefix.find("outputs.dm"), std::string::npos) << prefix;
  EXPECT_NE(prefix.find("prefixes mixed"), std::string::npos) << prefix;
  // A density added to a mass: not homogeneous in length (exponent 0 in one term, −3 in the
  // other, so no single power) — named with the dimension.
  const std::string unlike = error_of(mass_model("- m_nom\"", "- m_nom + rho_a\""));
  EXPECT_NE(unlike.find("scaling every length by 1.7"), std::string::npos) << unlike;
  EXPECT_NE(unlike.find("its unit mg says 1.7^0"), std::string::npos) << unlike;
  // rho_a and rho_a0 declared pure numbers (their kg/m³ forgotten): (rho_a − rho_a0) times the
  // m³/kg of (1/rho_W − 1/rho_R) is then added to 1. At the estimates rho_a = rho_a0 = 1.2, the
  // term vanishes and every scaling agrees; the second point (estimates + u) catches it.
  std::string forgotten = mass_model("rho_a0: kg/m^3", "rho_a0: 1");
  forgotten.replace(forgotten.find("rho_a: kg/m^3"), 13, "rho_a: 1");
  const std::string hidden = error_of(forgotten);
  EXPECT_NE(hidden.find("outputs.dm"), std::string::npos) << hidden;
  EXPECT_NE(hidden.find("scaling every"), std::string::npos) << hidden;
  // An output's exponent printed: dm declared mg², the expression gives mg.
  const std::string power = error_of(mass_model("dm: mg}", "dm: mg^2}"));
  EXPECT_NE(power.find("scales it by 1.7^1"), std::string::npos) << power;
  EXPECT_NE(power.find("says 1.7^2"), std::string::npos) << power;
  // Missing, unknown and unreadable units.
  const std::string missing = error_of(mass_model(", dm: mg}", "}"));
  EXPECT_NE(missing.find("missing: dm"), std::string::npos) << missing;
  const std::string unknown = error_of(mass_model("rho_R: kg/m^3,", "rho_RR: kg/m^3,"));
  EXPECT_NE(unknown.find("rho_RR"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("rho_R"), std::string::npos) << unknown;
  const std::string unreadable = error_of(mass_model("m_Rc: mg", "m_Rc: mgg"));
  EXPECT_NE(unreadable.find("m.yaml:11:"), std::string::npos) << unreadable;
  EXPECT_NE(unreadable.find("'mgg' is no unit symbol"), std::string::npos) << unreadable;
}

}  // namespace
}  // namespace gearmc::uncertainty

// Units of the quantities of an uncertainty model (the model file's `units:`) and the check that
// the model's expressions agree with them (docs/uncertainty.md, "Units"). A unit is a product of
// powers of symbols with optional SI prefixes — "mm", "kg/m^3", "N*m", "um/K", "m s^-2", "1" —
// read as a scale to SI and the exponents of the seven SI base dimensions. The check is
// numerical, so it needs no parse of the expressions: a model whose expressions agree with its
// units gives, with every input and constant converted to SI and every base dimension scaled by
// a factor λ_b, the output converted likewise: y(s·λ^e · x) = s_y λ^{e_y} y(x). It is tried at two
// points of the inputs (their estimates, and the estimates moved by their standard
// uncertainties, so a term that vanishes at one point cannot hide a disagreement), first per
// base dimension (a sum of a length and a mass fails here, naming the dimension and the exponent
// the expression has), then in SI (the scales: a model mixing mm and m in one sum fails here).
// Angles (rad, deg), %, ppm and degC are checked as pure numbers of scale 1: an expression such
// as sin(theta*_pi/180) or x/100 applies their scale itself.
#pragma once

#include <array>
#include <string>

namespace gearmc::uncertainty {

struct UncertaintyModel;

// The seven SI base dimensions, in this order.
inline constexpr std::array<const char*, 7> kBaseDimensions = {
    "length", "mass", "time", "current", "temperature", "amount", "luminous intensity"};

struct Unit {
  double scale = 1.0;                // the value in SI units is scale × the value in this unit
  std::array<double, 7> exponent{};  // of the base dimensions (m, kg, s, A, K, mol, cd)
};

// Parses a unit; throws std::invalid_argument saying what is wrong with it.
Unit parse_unit(const std::string& text);

// The SI base-unit form of a unit's dimension ("m^-3 kg", "1" when dimensionless).
std::string dimension_text(const Unit& unit);

// Checks `model`'s expressions against its units (model.units non-empty); throws InputError at
// the first output that disagrees, naming what it found.
void check_model_units(const UncertaintyModel& model);

}  // namespace gearmc::uncertainty

// A deterministic normal deviation written by the user as a muParser expression of
// L (roll length, mm), z (mm), tooth (1..z) and side (+1 R, -1 L), giving µm along the
// outward normal (docs/formats.md, "Deterministic deviations"). For what-if studies and
// cross-checks; it is added to the random deviations of a flank.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace gearmc {

// Thrown when the expression does not compile or does not evaluate; `position` is the
// 0-based character position muParser reports (or -1).
class ExpressionError : public std::runtime_error {
 public:
  ExpressionError(const std::string& message, int position)
      : std::runtime_error(message), position_(position) {}
  int position() const { return position_; }

 private:
  int position_;
};

// One compiled expression. Not thread-safe (muParser keeps evaluation state): copy it per
// thread; copies are independent.
class NormalExpression {
 public:
  explicit NormalExpression(const std::string& text);  // throws ExpressionError
  NormalExpression(const NormalExpression& other);
  NormalExpression& operator=(const NormalExpression& other);
  ~NormalExpression();

  const std::string& text() const { return text_; }
  // d(L, z) in µm on flank `side` (+1 R, -1 L) of `tooth`.
  double value_um(double L, double z, int tooth, double side) const;
  // Partial derivatives by the five-point central difference (muParser's Parser::Diff, with
  // the step kDerivativeStepMm below): f' = (-f(2h) + 8 f(h) - 8 f(-h) + f(-2h)) / (12 h),
  // truncation error (h^4 / 30) max|f^(5)|, rounding error about 1.5 eps max|f| / h. With
  // h = 1e-3 mm and a field of 100 µm that is 3e-11 µm/mm of rounding, and the truncation is
  // below 1e-6 µm/mm for features as narrow as sigma = 0.05 mm (f^(5) ~ f / sigma^5): a
  // slope error e moves the contact point by about R e, so C stays within 1e-2 nm for R <= 5 mm
  // (tested on a known analytic expression in tests/gears/normal_expression_test.cpp).
  // µm/mm.
  double d_dL(double L, double z, int tooth, double side) const;
  double d_dz(double L, double z, int tooth, double side) const;

  // Value and first and second partials at once (µm, µm/mm, µm/mm²), 13 evaluations: the
  // first partials by the five-point formula above, d_LL and d_zz by the five-point
  // (-f(2h) + 16 f(h) - 30 f(0) + 16 f(-h) - f(-2h)) / (12 h^2) (truncation (h^4 / 90)
  // max|f^(6)|, rounding about 5.3 eps max|f| / h^2 = 1e-7 µm/mm² at 100 µm) on the same
  // samples, d_Lz by the four-point cross difference (truncation (h^2 / 6)(|f_LLLz| +
  // |f_Lzzz|)). The second partials only steer the Newton iteration and the contact
  // certificate's curvature bounds; the converged contact depends on the first partials.
  struct Derivatives {
    double value, dL, dz, dLL, dLz, dzz;
  };
  Derivatives derivatives(double L, double z, int tooth, double side) const;
  static constexpr double kDerivativeStepMm = 1e-3;

 private:
  struct Impl;
  std::string text_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gearmc

// A deterministic normal deviation written by the user as a muParser expression of
// L (roll length, mm), z (mm), tooth (1..z) and side (+1 R, -1 L), giving µm along the
// outward normal (interface.md, "Deterministic deviations"). For what-if studies and
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
  // Central differences with step 1e-4 mm (exact to ~1e-8 relative for smooth expressions).
  double d_dL(double L, double z, int tooth, double side) const;
  double d_dz(double L, double z, int tooth, double side) const;

 private:
  struct Impl;
  std::string text_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace gearmc

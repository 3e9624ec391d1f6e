// muParser-backed deterministic normal deviations (see normal_expression.h).
#include "gears/normal_expression.h"

#include <muParser.h>

#include <cmath>

namespace gearmc {

struct NormalExpression::Impl {
  mu::Parser parser;
  // muParser binds variables by address: they live here, next to the parser.
  mutable double L = 0.0, z = 0.0, tooth = 1.0, side = 1.0;

  explicit Impl(const std::string& text) {
    try {
      parser.DefineVar("L", &L);
      parser.DefineVar("z", &z);
      parser.DefineVar("tooth", &tooth);
      parser.DefineVar("side", &side);
      parser.SetExpr(text);
      const double probe = parser.Eval();  // compiles; reports unknown names now
      (void)probe;
    } catch (const mu::Parser::exception_type& e) {
      throw ExpressionError(e.GetMsg(), static_cast<int>(e.GetPos()));
    }
  }
  double eval(double L_, double z_, int tooth_, double side_) const {
    L = L_;
    z = z_;
    tooth = tooth_;
    side = side_;
    try {
      return parser.Eval();
    } catch (const mu::Parser::exception_type& e) {
      throw ExpressionError(e.GetMsg(), static_cast<int>(e.GetPos()));
    }
  }
};

NormalExpression::NormalExpression(const std::string& text)
    : text_(text), impl_(std::make_unique<Impl>(text)) {}
NormalExpression::NormalExpression(const NormalExpression& other)
    : text_(other.text_), impl_(std::make_unique<Impl>(other.text_)) {}
NormalExpression& NormalExpression::operator=(const NormalExpression& other) {
  if (this != &other) {
    text_ = other.text_;
    impl_ = std::make_unique<Impl>(other.text_);
  }
  return *this;
}
NormalExpression::~NormalExpression() = default;

double NormalExpression::value_um(double L, double z, int tooth, double side) const {
  return impl_->eval(L, z, tooth, side);
}

double NormalExpression::d_dL(double L, double z, int tooth, double side) const {
  impl_->eval(L, z, tooth, side);  // sets z, tooth and side (and checks the expression)
  try {
    return impl_->parser.Diff(&impl_->L, L, kDerivativeStepMm);
  } catch (const mu::Parser::exception_type& e) {
    throw ExpressionError(e.GetMsg(), static_cast<int>(e.GetPos()));
  }
}
double NormalExpression::d_dz(double L, double z, int tooth, double side) const {
  impl_->eval(L, z, tooth, side);
  try {
    return impl_->parser.Diff(&impl_->z, z, kDerivativeStepMm);
  } catch (const mu::Parser::exception_type& e) {
    throw ExpressionError(e.GetMsg(), static_cast<int>(e.GetPos()));
  }
}

NormalExpression::Derivatives NormalExpression::derivatives(double L, double z, int tooth,
                                                            double side) const {
  constexpr double h = kDerivativeStepMm;
  auto f = [&](double a, double b) { return impl_->eval(a, b, tooth, side); };
  const double f0 = f(L, z);
  const double fLp = f(L + h, z), fLm = f(L - h, z), fLp2 = f(L + 2 * h, z), fLm2 = f(L - 2 * h, z);
  const double fzp = f(L, z + h), fzm = f(L, z - h), fzp2 = f(L, z + 2 * h), fzm2 = f(L, z - 2 * h);
  Derivatives d;
  d.value = f0;
  d.dL = (-fLp2 + 8.0 * fLp - 8.0 * fLm + fLm2) / (12.0 * h);
  d.dz = (-fzp2 + 8.0 * fzp - 8.0 * fzm + fzm2) / (12.0 * h);
  d.dLL = (-fLp2 + 16.0 * fLp - 30.0 * f0 + 16.0 * fLm - fLm2) / (12.0 * h * h);
  d.dzz = (-fzp2 + 16.0 * fzp - 30.0 * f0 + 16.0 * fzm - fzm2) / (12.0 * h * h);
  d.dLz = (f(L + h, z + h) - f(L + h, z - h) - f(L - h, z + h) + f(L - h, z - h)) / (4.0 * h * h);
  return d;
}

}  // namespace gearmc

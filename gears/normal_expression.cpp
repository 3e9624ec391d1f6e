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

namespace {
constexpr double kStep = 1e-4;  // mm
}

double NormalExpression::d_dL(double L, double z, int tooth, double side) const {
  return (value_um(L + kStep, z, tooth, side) - value_um(L - kStep, z, tooth, side)) /
         (2.0 * kStep);
}
double NormalExpression::d_dz(double L, double z, int tooth, double side) const {
  return (value_um(L, z + kStep, tooth, side) - value_um(L, z - kStep, tooth, side)) /
         (2.0 * kStep);
}

}  // namespace gearmc

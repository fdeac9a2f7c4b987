#include "cam/scaled.hpp"

#include <cmath>
#include <sstream>

#include "cam/error.hpp"

namespace polarcam {
namespace {

std::string scaled_name(const Curve& c, double k) {
  std::ostringstream os;
  os.precision(10);
  os << c.name() << " scaled " << k;
  return os.str();
}

class Scaled final : public Curve {
 public:
  Scaled(CurvePtr c, double k) : Curve(c->u_begin(), c->u_end(), c->closed(), scaled_name(*c, k)), c_(std::move(c)), k_(k) {}
  CurvePoint eval(double u, int order) const override {
    CurvePoint p = c_->eval(u, order);
    p.p = k_ * p.p;
    p.d1 = k_ * p.d1;
    p.d2 = k_ * p.d2;
    p.d3 = k_ * p.d3;
    return p;
  }
  std::vector<double> breakpoints() const override { return c_->breakpoints(); }
  double rounding_scale() const override { return k_ * c_->rounding_scale(); }

 private:
  CurvePtr c_;
  double k_;
};

}  // namespace

CurvePtr scale_curve(CurvePtr curve, double k) {
  if (!(k > 0.0) || !std::isfinite(k)) throw InputError("a size scale must be a number above zero");
  return std::make_shared<Scaled>(std::move(curve), k);
}

}  // namespace polarcam

// Expressions (cam/expression.hpp, cam/expr_curves.hpp): the first line of the input parsed as an expression of
// `u` (muparser's check, then polarcam's parser into the program that carries the derivatives) and evaluated with
// its three derivatives at a few points; when it parses, the curves made of it: r(t) of a polar curve and y(x) of
// a Cartesian one, and with the second line x(u), y(u) of a parametric one, each evaluated at its ends and middle.
#include <cmath>

#include "cam/expr_curves.hpp"
#include "cam/expression.hpp"
#include "fuzz/fuzz_common.hpp"

namespace {
void evaluate(const polarcam::CurvePtr& c) {
  for (double f : {0.0, 0.5, 1.0}) c->eval(c->u_begin() + f * (c->u_end() - c->u_begin()), 3);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace polarcam;
  const std::string text(fuzz::as_text(data, size));
  const size_t nl = text.find('\n');
  const std::string first = text.substr(0, nl);
  const std::string second = nl == std::string::npos ? std::string("u") : text.substr(nl + 1);
  const ExprConstants k{{"a", 2.0}, {"b", 0.5}};
  bool parses = false;
  fuzz::expect_typed([&] {
    const Expression e(first, {"u", "t"}, k, "fuzz");
    double d[4];
    for (double x : {-1.0, 0.0, 0.5, 3.0}) {
      e.derivatives(x, 3, d);
      e.excess(x);
    }
    parses = true;
  });
  if (!parses) return 0;
  fuzz::expect_typed([&] { evaluate(make_polar_expr(first, 0.0, 2 * M_PI, false, 1e-3, k)); });
  fuzz::expect_typed([&] { evaluate(make_cartesian_expr(first, -0.05, 0.05, 1e-3, k)); });
  fuzz::expect_typed([&] { evaluate(make_parametric_expr(first, second, 0.0, 1.0, true, 1e-3, k)); });
  return 0;
}

// Curves typed as expressions (cam/expr_curves.hpp, muparser): the first line of the input as r(t) of a polar
// curve and y(x) of a Cartesian one, the first two lines as x(u), y(u) of a parametric one, each with a named
// constant; every curve made is evaluated with its derivatives at its ends and its middle.
#include <cmath>

#include "cam/expr_curves.hpp"
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
  fuzz::expect_typed([&] { evaluate(make_polar_expr(first, 0.0, 2 * M_PI, false, 1e-3, k)); });
  fuzz::expect_typed([&] { evaluate(make_cartesian_expr(first, -0.05, 0.05, 1e-3, k)); });
  fuzz::expect_typed([&] { evaluate(make_parametric_expr(first, second, 0.0, 1.0, true, 1e-3, k)); });
  return 0;
}

#pragma once
// A user's expression of one variable (muparser's syntax) with its first three derivatives, exact to rounding:
// forward-mode automatic differentiation. The text is parsed once into a small postfix program; each evaluation
// carries, through every operation, the value and the first `order` derivatives with respect to the variable (a
// jet), by the product, quotient and chain rules (Faa di Bruno's formula to the third order). Nothing is
// approximated: the derivatives carry only the rounding errors of their own arithmetic, like the value. The
// evaluation order is the order of the text, so the same text gives the same bits on every run.
//
// Accepted: numbers, the variable (under one or more names), named constants, `pi`, muparser's own constants
// (`_pi`, `_e`, with muparser's values), + - * / ^
// (right-associative, above unary minus: -x^2 = -(x^2), as in muparser), parentheses and the smooth functions
// sin cos tan asin acos atan sinh cosh tanh asinh acosh atanh exp log ln log2 log10 sqrt, and abs, min, max
// (smooth but where their arguments meet: there the derivative is the one on the side of increasing variable),
// sum, avg. Refused, in one line naming the function: sign and rint (steps: a curve through them jumps), the
// comparison and logical operators and `?:` (the same), and several comma-separated expressions.
//
// Evaluation is thread-safe: a compiled expression is immutable.
#include <map>
#include <string>
#include <vector>

namespace polarcam {

// The longest expression text read: far beyond any contour's formula, and it bounds the depth of the recursions that
// parse and flatten a long chain of operations.
inline constexpr size_t kMaxExpressionLength = 10000;

class Expression {
 public:
  // Parses `text`. `variables` are names of the one variable (e.g. {"u", "t"}); `constants` named values (they
  // and `pi` are constants, their derivatives 0). `key` names the expression in messages. Throws InputError
  // (place `key`) for a syntax error, an unknown name or a refused function, naming it.
  Expression(const std::string& text, const std::vector<std::string>& variables,
             const std::map<std::string, double>& constants, const std::string& key);

  // The value at x.
  double operator()(double x) const;
  // out[0] = f(x), out[k] = the k-th derivative at x for k <= order (0..3); out[k] = 0 above order.
  void derivatives(double x, int order, double out[4]) const;

  // The size of the numbers f(x) is computed from beyond |f(x)| itself: 0 when nothing cancels, about 1e6 for
  // 1e6 + x - 1e6. The value's rounding error is a few units in the last place of |f(x)| + excess(x).
  double excess(double x) const;

  const std::string& text() const { return text_; }
  const std::string& key() const { return key_; }

  // One instruction of the postfix program (public for the implementation's helpers only).
  struct Op {
    int code = 0;     // what it does (expression.cpp)
    int n = 0;        // arguments of a function with several (min, max, sum, avg)
    double c = 0.0;   // the value of a constant; the exponent of a constant power
  };

 private:
  std::string text_, key_;
  std::vector<Op> program_;
  int depth_ = 0;  // the largest stack the program needs
};

}  // namespace polarcam

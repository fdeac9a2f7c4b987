#include "cam/expression.hpp"

#include <muParser.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "cam/error.hpp"

namespace polarcam {
namespace {

enum Code : int {
  kConst, kVar, kAdd, kSub, kMul, kDiv, kNeg, kPowC, kPow,
  kSin, kCos, kTan, kAsin, kAcos, kAtan, kSinh, kCosh, kTanh, kAsinh, kAcosh, kAtanh,
  kExp, kLog, kLog2, kLog10, kSqrt, kAbs, kMin, kMax, kSum, kAvg
};

struct Fn {
  const char* name;
  int code;
  int arity;  // -1: one or more
};
constexpr Fn kFunctions[] = {
    {"sin", kSin, 1},     {"cos", kCos, 1},     {"tan", kTan, 1},     {"asin", kAsin, 1},   {"acos", kAcos, 1},
    {"atan", kAtan, 1},   {"sinh", kSinh, 1},   {"cosh", kCosh, 1},   {"tanh", kTanh, 1},   {"asinh", kAsinh, 1},
    {"acosh", kAcosh, 1}, {"atanh", kAtanh, 1}, {"exp", kExp, 1},     {"log", kLog, 1},     {"ln", kLog, 1},
    {"log2", kLog2, 1},   {"log10", kLog10, 1}, {"sqrt", kSqrt, 1},   {"abs", kAbs, 1},     {"min", kMin, -1},
    {"max", kMax, -1},    {"sum", kSum, -1},    {"avg", kAvg, -1},
};

// A parsed expression before it is flattened into the program.
struct Node {
  int code = kConst;
  double c = 0.0;
  bool konst = true;  // does not depend on the variable
  std::vector<Node> kids;
};

// A value and its first three derivatives.
struct Jet {
  double d[4];
};

// h = phi(g) by the chain rule: phi[k] is the k-th derivative of phi at g.d[0].
inline Jet chain(const Jet& g, const double phi[4], int order) {
  Jet h{{phi[0], 0.0, 0.0, 0.0}};
  if (order >= 1) h.d[1] = phi[1] * g.d[1];
  if (order >= 2) h.d[2] = phi[2] * g.d[1] * g.d[1] + phi[1] * g.d[2];
  if (order >= 3) h.d[3] = phi[3] * g.d[1] * g.d[1] * g.d[1] + 3.0 * phi[2] * g.d[1] * g.d[2] + phi[1] * g.d[3];
  return h;
}

inline Jet mul(const Jet& f, const Jet& g, int order) {
  Jet h{{f.d[0] * g.d[0], 0.0, 0.0, 0.0}};
  if (order >= 1) h.d[1] = f.d[1] * g.d[0] + f.d[0] * g.d[1];
  if (order >= 2) h.d[2] = f.d[2] * g.d[0] + 2.0 * f.d[1] * g.d[1] + f.d[0] * g.d[2];
  if (order >= 3) h.d[3] = f.d[3] * g.d[0] + 3.0 * (f.d[2] * g.d[1] + f.d[1] * g.d[2]) + f.d[0] * g.d[3];
  return h;
}

// h = f / g from h g = f.
inline Jet div(const Jet& f, const Jet& g, int order) {
  Jet h{{f.d[0] / g.d[0], 0.0, 0.0, 0.0}};
  if (order >= 1) h.d[1] = (f.d[1] - h.d[0] * g.d[1]) / g.d[0];
  if (order >= 2) h.d[2] = (f.d[2] - 2.0 * h.d[1] * g.d[1] - h.d[0] * g.d[2]) / g.d[0];
  if (order >= 3) h.d[3] = (f.d[3] - 3.0 * (h.d[2] * g.d[1] + h.d[1] * g.d[2]) - h.d[0] * g.d[3]) / g.d[0];
  return h;
}

// Lexicographic comparison of two jets up to `order`: the one smaller just after the point (the right-hand side).
inline bool less_after(const Jet& a, const Jet& b, int order) {
  for (int k = 0; k <= order; ++k)
    if (a.d[k] != b.d[k]) return a.d[k] < b.d[k];
  return false;
}

// phi and its derivatives of a function of one argument at x; false for a code that is not one.
bool unary(int code, double x, double c, double phi[4]) {
  switch (code) {
    case kNeg: phi[0] = -x, phi[1] = -1, phi[2] = phi[3] = 0; return true;
    case kPowC: {
      // x^c; a term whose coefficient is zero is left out (x = 0 with a whole exponent: 0 * inf)
      phi[0] = std::pow(x, c);
      double k = c;
      for (int j = 1; j <= 3; ++j) {
        phi[j] = k == 0.0 ? 0.0 : k * std::pow(x, c - j);
        k *= c - j;
      }
      return true;
    }
    case kSin: {
      const double s = std::sin(x), co = std::cos(x);
      phi[0] = s, phi[1] = co, phi[2] = -s, phi[3] = -co;
      return true;
    }
    case kCos: {
      const double s = std::sin(x), co = std::cos(x);
      phi[0] = co, phi[1] = -s, phi[2] = -co, phi[3] = s;
      return true;
    }
    case kTan: {
      const double t = std::tan(x), d1 = 1.0 + t * t, d2 = 2.0 * t * d1;
      phi[0] = t, phi[1] = d1, phi[2] = d2, phi[3] = 2.0 * d1 * d1 + 2.0 * t * d2;
      return true;
    }
    case kAsin:
    case kAcos: {
      const double w = 1.0 / std::sqrt(1.0 - x * x), w3 = w * w * w, sg = code == kAsin ? 1.0 : -1.0;
      phi[0] = code == kAsin ? std::asin(x) : std::acos(x);
      phi[1] = sg * w, phi[2] = sg * x * w3, phi[3] = sg * w3 * (1.0 + 3.0 * x * x * w * w);
      return true;
    }
    case kAtan: {
      const double w = 1.0 / (1.0 + x * x);
      phi[0] = std::atan(x), phi[1] = w, phi[2] = -2.0 * x * w * w, phi[3] = (6.0 * x * x - 2.0) * w * w * w;
      return true;
    }
    case kSinh:
    case kCosh: {
      const double sh = std::sinh(x), ch = std::cosh(x);
      if (code == kSinh) phi[0] = sh, phi[1] = ch, phi[2] = sh, phi[3] = ch;
      else phi[0] = ch, phi[1] = sh, phi[2] = ch, phi[3] = sh;
      return true;
    }
    case kTanh: {
      const double t = std::tanh(x), d1 = 1.0 - t * t, d2 = -2.0 * t * d1;
      phi[0] = t, phi[1] = d1, phi[2] = d2, phi[3] = -2.0 * d1 * d1 - 2.0 * t * d2;
      return true;
    }
    case kAsinh: {
      const double w = 1.0 / std::sqrt(1.0 + x * x), w3 = w * w * w;
      phi[0] = std::asinh(x), phi[1] = w, phi[2] = -x * w3, phi[3] = (2.0 * x * x - 1.0) * w3 * w * w;
      return true;
    }
    case kAcosh: {
      const double w = 1.0 / std::sqrt(x * x - 1.0), w3 = w * w * w;
      phi[0] = std::acosh(x), phi[1] = w, phi[2] = -x * w3, phi[3] = (2.0 * x * x + 1.0) * w3 * w * w;
      return true;
    }
    case kAtanh: {
      const double w = 1.0 / (1.0 - x * x);
      phi[0] = std::atanh(x), phi[1] = w, phi[2] = 2.0 * x * w * w, phi[3] = (2.0 + 6.0 * x * x) * w * w * w;
      return true;
    }
    case kExp: phi[0] = phi[1] = phi[2] = phi[3] = std::exp(x); return true;
    case kLog:
    case kLog2:
    case kLog10: {
      const double k = code == kLog ? 1.0 : code == kLog2 ? std::numbers::ln2 : std::numbers::ln10;
      phi[0] = code == kLog ? std::log(x) : code == kLog2 ? std::log2(x) : std::log10(x);
      phi[1] = 1.0 / (k * x), phi[2] = -phi[1] / x, phi[3] = -2.0 * phi[2] / x;
      return true;
    }
    case kSqrt: {
      const double s = std::sqrt(x);
      phi[0] = s, phi[1] = 0.5 / s, phi[2] = -0.5 * phi[1] / x, phi[3] = -1.5 * phi[2] / x;
      return true;
    }
    default: return false;
  }
}

// Runs a program: the value and derivatives up to `order` at x.
Jet run(const std::vector<Expression::Op>& prog, int depth, double x, int order) {
  Jet small[32];
  small[0] = Jet{{0.0, 0.0, 0.0, 0.0}};  // an empty program is 0 (it cannot be; the compiler does not know)
  std::vector<Jet> big;
  Jet* st = small;
  if (depth > 32) {
    big.resize(static_cast<size_t>(depth));
    st = big.data();
  }
  int sp = 0;  // number of jets on the stack
  for (const Expression::Op& op : prog) {
    switch (op.code) {
      case kConst: st[sp++] = Jet{{op.c, 0.0, 0.0, 0.0}}; break;
      case kVar: st[sp++] = Jet{{x, 1.0, 0.0, 0.0}}; break;
      case kAdd:
      case kSub: {
        Jet& a = st[sp - 2];
        const Jet& b = st[sp - 1];
        for (int k = 0; k <= order; ++k) a.d[k] = op.code == kAdd ? a.d[k] + b.d[k] : a.d[k] - b.d[k];
        --sp;
        break;
      }
      case kMul: st[sp - 2] = mul(st[sp - 2], st[sp - 1], order), --sp; break;
      case kDiv: st[sp - 2] = div(st[sp - 2], st[sp - 1], order), --sp; break;
      case kPow: {
        // f^g = exp(g log f): the value as pow gives it, the derivatives through the jets of log f and g log f
        const Jet f = st[sp - 2], g = st[sp - 1];
        double phi[4];
        unary(kLog, f.d[0], 0.0, phi);
        const Jet p = mul(g, chain(f, phi, order), order);
        const double v = std::pow(f.d[0], g.d[0]);
        const double e[4] = {v, v, v, v};
        st[sp - 2] = chain(p, e, order);
        --sp;
        break;
      }
      case kAbs: {
        Jet& a = st[sp - 1];
        double s = 1.0;  // the sign of the argument, or at its zero the sign it takes just after
        for (int k = 0; k <= order; ++k)
          if (a.d[k] != 0.0) {
            s = a.d[k] < 0.0 ? -1.0 : 1.0;
            break;
          }
        for (int k = 0; k <= order; ++k) a.d[k] *= s;
        a.d[0] = std::abs(a.d[0]);
        break;
      }
      case kMin:
      case kMax: {
        const int first = sp - op.n;
        int best = first;
        for (int i = first + 1; i < sp; ++i)
          if (op.code == kMin ? less_after(st[i], st[best], order) : less_after(st[best], st[i], order)) best = i;
        st[first] = st[best];
        sp = first + 1;
        break;
      }
      case kSum:
      case kAvg: {
        const int first = sp - op.n;
        for (int i = first + 1; i < sp; ++i)
          for (int k = 0; k <= order; ++k) st[first].d[k] += st[i].d[k];
        if (op.code == kAvg)
          for (int k = 0; k <= order; ++k) st[first].d[k] /= op.n;
        sp = first + 1;
        break;
      }
      default: {
        double phi[4];
        unary(op.code, st[sp - 1].d[0], op.c, phi);
        st[sp - 1] = chain(st[sp - 1], phi, order);
      }
    }
  }
  Jet r = st[0];
  for (int k = order + 1; k < 4; ++k) r.d[k] = 0.0;
  return r;
}

// The value and the size of the numbers it is computed from (T): the absolute rounding error of the value is a
// few units in the last place of T. Constants and the variable are taken as exact; a sum carries the sizes of
// both terms (T = |value| when nothing cancels), a product or quotient the relative sizes of its factors, a
// function phi(g) the error of its argument, |phi'(g)| (T_g - |g|), above its own value.
struct Sized {
  double v, T;
};
Sized run_sized(const std::vector<Expression::Op>& prog, double x) {
  std::vector<Sized> st;
  st.reserve(prog.size());
  for (const Expression::Op& op : prog) {
    const size_t sp = st.size();
    switch (op.code) {
      case kConst: st.push_back({op.c, std::abs(op.c)}); break;
      case kVar: st.push_back({x, std::abs(x)}); break;
      case kAdd:
      case kSub:
      case kMul:
      case kDiv: {
        const Sized a = st[sp - 2], b = st[sp - 1];
        st.pop_back();
        Sized& r = st.back();
        if (op.code == kAdd || op.code == kSub) r = {op.code == kAdd ? a.v + b.v : a.v - b.v, a.T + b.T};
        else if (op.code == kMul) r = {a.v * b.v, a.T * b.T};
        else r = {a.v / b.v, a.T * b.T / (b.v * b.v)};
        break;
      }
      case kPow: {
        // f^g = exp(g log f)
        const Sized f = st[sp - 2], g = st[sp - 1];
        st.pop_back();
        const double lg = std::log(f.v), Tl = std::abs(lg) + (f.T - std::abs(f.v)) / std::abs(f.v);
        const double p = g.v * lg, Tp = g.T * Tl, v = std::pow(f.v, g.v);
        st.back() = {v, std::abs(v) * (1.0 + Tp - std::abs(p))};
        break;
      }
      case kAbs: st.back().v = std::abs(st.back().v); break;
      case kMin:
      case kMax: {
        const size_t first = sp - static_cast<size_t>(op.n);
        size_t best = first;
        for (size_t i = first + 1; i < sp; ++i)
          if (op.code == kMin ? st[i].v < st[best].v : st[i].v > st[best].v) best = i;
        st[first] = st[best];
        st.resize(first + 1);
        break;
      }
      case kSum:
      case kAvg: {
        const size_t first = sp - static_cast<size_t>(op.n);
        for (size_t i = first + 1; i < sp; ++i) st[first].v += st[i].v, st[first].T += st[i].T;
        if (op.code == kAvg) st[first].v /= op.n, st[first].T /= op.n;
        st.resize(first + 1);
        break;
      }
      default: {
        double phi[4];
        Sized& g = st.back();
        unary(op.code, g.v, op.c, phi);
        g = {phi[0], std::abs(phi[0]) + std::abs(phi[1]) * (g.T - std::abs(g.v))};
      }
    }
  }
  return st.empty() ? Sized{0.0, 0.0} : st.back();
}

// Recursive descent over muparser's grammar:
//   sum     = product { ("+" | "-") product }
//   product = unary { ("*" | "/") unary }
//   unary   = ("-" | "+") unary | power
//   power   = primary [ "^" unary ]          (right-associative, above unary minus)
//   primary = number | name | name "(" sum { "," sum } ")" | "(" sum ")"
class Parser {
 public:
  Parser(const std::string& text, const std::vector<std::string>& vars, const std::map<std::string, double>& consts,
         const std::string& key)
      : s_(text), vars_(vars), consts_(consts), key_(key) {}

  Node parse() {
    Node n = sum();
    skip();
    if (i_ < s_.size()) unexpected();
    return n;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("'" + s_ + "': " + what, key_);
  }
  [[noreturn]] void unexpected() const {
    const char ch = s_[i_];
    std::string op(1, ch);
    if (std::string("<>=!&|").find(ch) != std::string::npos) {
      // the whole operator: <, <=, ==, !=, &&, ||
      for (size_t j = i_ + 1; j < s_.size() && std::string("=&|").find(s_[j]) != std::string::npos; ++j) op += s_[j];
      const bool logic = ch == '&' || ch == '|';
      fail("the " + std::string(logic ? "logical" : "comparison") + " operator '" + op +
           "': a curve would jump where it switches; the digitizer needs a curve with derivatives (split the contour "
           "into pieces instead)");
    }
    if (ch == '?' || ch == ':')
      fail("'?:' chooses between expressions: a curve would jump where the choice changes; the digitizer needs a "
           "curve with derivatives (split the contour into pieces instead)");
    if (ch == ',') fail("one expression is expected, not several separated by ','");
    fail("unexpected '" + op + "' at position " + std::to_string(i_ + 1));
  }
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(char ch) {
    skip();
    if (i_ < s_.size() && s_[i_] == ch) {
      ++i_;
      return true;
    }
    return false;
  }

  // a ')', else the refused operator that stands in its place, else `missing`
  void close(const std::string& missing) {
    if (eat(')')) return;
    if (i_ < s_.size() && std::string("<>=!&|?:,").find(s_[i_]) != std::string::npos) unexpected();
    fail(missing);
  }

  static Node binary(int code, Node a, Node b) {
    Node n;
    n.code = code;
    n.konst = a.konst && b.konst;
    n.kids.push_back(std::move(a));
    n.kids.push_back(std::move(b));
    return n;
  }

  // Nesting (parentheses, function calls, signs, exponents) is bounded, so that the recursion is; muparser bounds
  // the length of the text, and so the height of the tree.
  struct Nest {
    Parser& p;
    explicit Nest(Parser& q) : p(q) {
      if (++p.nest_ > kMaxNesting)
        p.fail("nested too deeply (parentheses, functions, signs and exponents within one another, about " +
               std::to_string(kMaxNesting / 2) + " at most): write it more simply");
    }
    ~Nest() { --p.nest_; }
  };
  static constexpr int kMaxNesting = 256;

  Node sum() {
    Nest guard(*this);
    Node a = product();
    for (;;) {
      if (eat('+')) a = binary(kAdd, std::move(a), product());
      else if (eat('-')) a = binary(kSub, std::move(a), product());
      else return a;
    }
  }
  Node product() {
    Node a = unary_minus();
    for (;;) {
      if (eat('*')) a = binary(kMul, std::move(a), unary_minus());
      else if (eat('/')) a = binary(kDiv, std::move(a), unary_minus());
      else return a;
    }
  }
  Node unary_minus() {
    Nest guard(*this);
    if (eat('-')) {
      Node n;
      n.code = kNeg;
      n.kids.push_back(unary_minus());
      n.konst = n.kids[0].konst;
      return n;
    }
    if (eat('+')) return unary_minus();
    return power();
  }
  Node power() {
    Node a = primary();
    if (eat('^')) return binary(kPow, std::move(a), unary_minus());
    return a;
  }
  Node primary() {
    skip();
    if (i_ >= s_.size()) fail("the expression ends too early");
    const char ch = s_[i_];
    if (ch == '(') {
      ++i_;
      Node n = sum();
      close("a ')' is missing");
      return n;
    }
    if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(ch)) || ch == '_') return name();
    unexpected();
  }
  Node number() {
    const size_t b = i_;
    while (i_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.')) ++i_;
    if (i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      size_t j = i_ + 1;
      if (j < s_.size() && (s_[j] == '+' || s_[j] == '-')) ++j;
      if (j < s_.size() && std::isdigit(static_cast<unsigned char>(s_[j]))) {
        i_ = j;
        while (i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_]))) ++i_;
      }
    }
    const std::string lit = s_.substr(b, i_ - b);
    char* end = nullptr;
    Node n;
    n.c = std::strtod(lit.c_str(), &end);
    if (end != lit.c_str() + lit.size() || lit == ".") fail("'" + lit + "' is not a number");
    return n;
  }
  Node name() {
    const size_t b = i_;
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) ++i_;
    const std::string id = s_.substr(b, i_ - b);
    skip();
    if (i_ < s_.size() && s_[i_] == '(') return call(id);
    Node n;
    if (std::find(vars_.begin(), vars_.end(), id) != vars_.end()) {
      n.code = kVar;
      n.konst = false;
    } else if (auto it = consts_.find(id); it != consts_.end()) {
      n.c = it->second;
    } else {
      fail("unknown name '" + id + "'");
    }
    return n;
  }
  Node call(const std::string& id) {
    const Fn* fn = nullptr;
    for (const Fn& f : kFunctions)
      if (id == f.name) fn = &f;
    if (!fn) {
      if (id == "sign" || id == "rint")
        fail("the function " + id + "() is a step: the curve would jump where it steps; the digitizer needs a curve "
             "with derivatives (smooth functions, abs, min, max; or split the contour into pieces)");
      fail("unknown function '" + id + "'");
    }
    ++i_;  // '('
    Node n;
    n.code = fn->code;
    do n.kids.push_back(sum());
    while (eat(','));
    close("a ')' is missing after the arguments of " + id + "()");
    if (fn->arity > 0 && static_cast<int>(n.kids.size()) != fn->arity)
      fail(id + "() takes " + std::to_string(fn->arity) + " argument");
    for (const Node& k : n.kids) n.konst = n.konst && k.konst;
    return n;
  }

  const std::string& s_;
  const std::vector<std::string>& vars_;
  const std::map<std::string, double>& consts_;
  const std::string& key_;
  size_t i_ = 0;
  int nest_ = 0;
};

// Flattens n into postfix; a part that does not depend on the variable becomes its value (computed as the
// program would compute it), and a power with such an exponent the constant power.
// `fold` false: n itself is flattened even when constant (its parts are still folded), so that folding a constant
// part runs a program of its node and its parts' values: linear in the size of the expression (copying the part to
// flatten it was quadratic in the length of a chain of constant products).
void emit(const Node& n, std::vector<Expression::Op>& prog, bool fold = true) {
  if (fold && n.konst && n.code != kConst) {
    std::vector<Expression::Op> sub;
    emit(n, sub, false);
    prog.push_back({kConst, 0, run(sub, static_cast<int>(sub.size()), 0.0, 0).d[0]});
    return;
  }
  if (n.code == kPow && n.kids[1].konst) {
    emit(n.kids[0], prog);
    std::vector<Expression::Op> sub;
    emit(n.kids[1], sub);
    prog.push_back({kPowC, 0, sub.back().c});
    return;
  }
  for (const Node& k : n.kids) emit(k, prog);
  prog.push_back({n.code, static_cast<int>(n.kids.size()), n.c});
}

int stack_depth(const std::vector<Expression::Op>& prog) {
  int sp = 0, most = 0;
  for (const auto& op : prog) {
    if (op.code == kConst || op.code == kVar) ++sp;
    else if (op.code == kAdd || op.code == kSub || op.code == kMul || op.code == kDiv || op.code == kPow) --sp;
    else if (op.code == kMin || op.code == kMax || op.code == kSum || op.code == kAvg) sp -= op.n - 1;
    most = std::max(most, sp);
  }
  return most;
}

}  // namespace

Expression::Expression(const std::string& text, const std::vector<std::string>& variables,
                       const std::map<std::string, double>& constants, const std::string& key)
    : text_(text), key_(key) {
  if (text.size() > kMaxExpressionLength)
    throw InputError("an expression of " + std::to_string(text.size()) + " characters: at most " +
                         std::to_string(kMaxExpressionLength) + " are read (a contour's formula is far shorter)",
                     key);
  // muparser checks the syntax first, with its messages, so that what it refuses is refused as before; its
  // constants (ours, the job's and its own _pi and _e, with muparser's values) are the ones the text may name
  std::map<std::string, double> names;
  try {
    mu::Parser p;
    double var = 0.0;
    p.DefineConst("pi", std::numbers::pi);
    for (const auto& [k, v] : constants) p.DefineConst(k, v);
    for (const auto& v : variables) p.DefineVar(v, &var);
    p.SetExpr(text);
    p.Eval();
    for (const auto& [k, v] : p.GetConst()) names[k] = v;
  } catch (mu::Parser::exception_type& e) {
    std::string msg = "'" + text + "': " + e.GetMsg();
    if (e.GetCode() == mu::ecUNASSIGNABLE_TOKEN) {
      // a name it does not know: say which it does
      std::string vars;
      for (const auto& v : variables) vars += (vars.empty() ? "" : " or ") + v;
      msg += " (the variable is " + vars + "; the constants are pi and those of [contour.constants])";
    }
    throw InputError(msg, key);
  }
  const Node root = Parser(text, variables, names, key).parse();
  emit(root, program_);
  depth_ = stack_depth(program_);
}

double Expression::excess(double x) const {
  const Sized r = run_sized(program_, x);
  const double e = r.T - std::abs(r.v);
  return e > 0.0 ? e : 0.0;
}

double Expression::operator()(double x) const { return run(program_, depth_, x, 0).d[0]; }

void Expression::derivatives(double x, int order, double out[4]) const {
  const Jet j = run(program_, depth_, x, std::clamp(order, 0, 3));
  for (int k = 0; k < 4; ++k) out[k] = j.d[k];
}

}  // namespace polarcam

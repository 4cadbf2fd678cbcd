#include "scenes/species/lsystem_file.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <string_view>
#include <vector>

namespace sylva {

namespace {

constexpr int kMaxNesting = 32;  // parentheses inside one expression

std::string_view trim_blanks(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// One line with its comment removed and the accepted Unicode spellings (− ∧ →) made ASCII.
std::string normalise_line(std::string_view raw) {
  std::string out;
  bool quoted = false;
  for (size_t i = 0; i < raw.size(); ++i) {
    const char c = raw[i];
    if (c == '"') quoted = !quoted;
    if (c == '#' && !quoted) break;
    const std::string_view rest = raw.substr(i);
    if (rest.starts_with("\xE2\x88\x92")) {  // U+2212 minus
      out += '-';
      i += 2;
    } else if (rest.starts_with("\xE2\x88\xA7")) {  // U+2227 logical and, ABOP's pitch up
      out += '^';
      i += 2;
    } else if (rest.starts_with("\xE2\x86\x92")) {  // U+2192 arrow
      out += "->";
      i += 2;
    } else {
      out += c;
    }
  }
  return std::string(trim_blanks(out));
}

bool is_ident_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// A turtle/module symbol: printable ASCII other than digits, spaces and the format's punctuation.
bool is_symbol(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u <= 0x20 || u >= 0x7f) return false;
  if (std::isdigit(u)) return false;
  return c != '(' && c != ')' && c != ',' && c != ':' && c != '#' && c != '=' && c != '"';
}

std::string show(char c) {
  const auto u = static_cast<unsigned char>(c);
  if (u < 0x20 || u >= 0x7f) return fmt::format("byte 0x{:02x}", static_cast<unsigned>(u));
  return fmt::format("'{}'", c);
}

// Recursive-descent expression compiler to LsExpr postfix code.
class ExprParser {
 public:
  ExprParser(std::string_view text, const std::vector<std::string>& formals,
             const std::map<std::string, float>& defines, const std::function<void(const std::string&)>& fail)
      : s_(text), formals_(formals), defines_(defines), fail_(fail) {}

  // Parses one expression starting at `pos`; stops before a top-level ',' or ')' or at the end.
  LsExpr parse(size_t& pos) {
    pos_ = pos;
    depth_ = 0;
    out_.code.clear();
    parse_or();
    pos = pos_;
    if (!validate_ls_expr(out_, static_cast<int>(formals_.size()))) fail_("expression is too deeply nested");
    return out_;
  }

 private:
  void skip() {
    while (pos_ < s_.size() && (s_[pos_] == ' ' || s_[pos_] == '\t')) ++pos_;
  }
  bool eat(std::string_view tok) {
    skip();
    if (s_.substr(pos_).starts_with(tok)) {
      pos_ += tok.size();
      return true;
    }
    return false;
  }
  void emit(LsOp op, float value = 0, uint8_t index = 0) {
    if (out_.code.size() > 4096) fail_("expression is too long");
    out_.code.push_back(LsInstr{op, index, value});
  }
  std::string near() const {
    if (pos_ >= s_.size()) return "the end of the expression";
    return fmt::format("'{}'", s_.substr(pos_, 12));
  }

  void parse_or() {
    parse_and();
    while (eat("||")) {
      parse_and();
      emit(LsOp::Or);
    }
  }
  void parse_and() {
    parse_cmp();
    while (eat("&&")) {
      parse_cmp();
      emit(LsOp::And);
    }
  }
  void parse_cmp() {
    parse_add();
    for (;;) {
      LsOp op;
      if (eat("=="))
        op = LsOp::Eq;
      else if (eat("!="))
        op = LsOp::Ne;
      else if (eat("<="))
        op = LsOp::Le;
      else if (eat(">="))
        op = LsOp::Ge;
      else if (eat("<"))
        op = LsOp::Lt;
      else if (eat(">"))
        op = LsOp::Gt;
      else
        return;
      parse_add();
      emit(op);
    }
  }
  void parse_add() {
    parse_mul();
    for (;;) {
      skip();
      // "->" ends a condition: it is not a minus.
      if (s_.substr(pos_).starts_with("->")) return;
      if (eat("+")) {
        parse_mul();
        emit(LsOp::Add);
      } else if (eat("-")) {
        parse_mul();
        emit(LsOp::Sub);
      } else {
        return;
      }
    }
  }
  void parse_mul() {
    parse_unary();
    for (;;) {
      if (eat("*")) {
        parse_unary();
        emit(LsOp::Mul);
      } else if (eat("/")) {
        parse_unary();
        emit(LsOp::Div);
      } else {
        return;
      }
    }
  }
  void parse_unary() {
    skip();
    if (s_.substr(pos_).starts_with("->")) fail_("expected a value before '->'");
    if (eat("-")) {
      nest([&] { parse_unary(); });
      emit(LsOp::Neg);
    } else if (eat("!")) {
      nest([&] { parse_unary(); });
      emit(LsOp::Not);
    } else if (eat("+")) {
      nest([&] { parse_unary(); });
    } else {
      parse_power();
    }
  }
  void parse_power() {
    parse_primary();
    if (eat("^")) {
      nest([&] { parse_unary(); });  // right-associative: a^-b^c = a^(-(b^c))
      emit(LsOp::Pow);
    }
  }
  template <typename F>
  void nest(F&& f) {
    if (++depth_ > kMaxNesting) fail_(fmt::format("expression nested deeper than {} levels", kMaxNesting));
    f();
    --depth_;
  }
  void parse_primary() {
    skip();
    if (pos_ >= s_.size()) fail_("expected a value at the end of the expression");
    const char c = s_[pos_];
    if (c == '(') {
      ++pos_;
      nest([&] { parse_or(); });
      if (!eat(")")) fail_(fmt::format("expected ')' at {}", near()));
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      float v = 0;
      const char* begin = s_.data() + pos_;
      const auto [end, ec] = std::from_chars(begin, s_.data() + s_.size(), v);
      if (ec != std::errc() || !std::isfinite(v)) fail_(fmt::format("bad number at {}", near()));
      pos_ += static_cast<size_t>(end - begin);
      emit(LsOp::Const, v);
      return;
    }
    if (!is_ident_start(c)) fail_(fmt::format("expected a number, name or '(' at {}", near()));
    const size_t start = pos_;
    while (pos_ < s_.size() && is_ident_char(s_[pos_])) ++pos_;
    const std::string name(s_.substr(start, pos_ - start));
    static const std::map<std::string, std::pair<LsOp, int>> functions = {
        {"sqrt", {LsOp::Sqrt, 1}}, {"abs", {LsOp::Abs, 1}}, {"floor", {LsOp::Floor, 1}}, {"sin", {LsOp::Sin, 1}},
        {"cos", {LsOp::Cos, 1}},   {"min", {LsOp::Min, 2}}, {"max", {LsOp::Max, 2}}};
    skip();
    if (const auto f = functions.find(name); f != functions.end() && pos_ < s_.size() && s_[pos_] == '(') {
      ++pos_;
      for (int k = 0; k < f->second.second; ++k) {
        if (k > 0 && !eat(",")) fail_(fmt::format("'{}' takes {} arguments", name, f->second.second));
        nest([&] { parse_or(); });
      }
      if (!eat(")")) fail_(fmt::format("expected ')' closing '{}(' at {}", name, near()));
      emit(f->second.first);
      return;
    }
    for (size_t k = 0; k < formals_.size(); ++k)
      if (formals_[k] == name) return emit(LsOp::Param, 0, static_cast<uint8_t>(k));
    if (const auto d = defines_.find(name); d != defines_.end()) return emit(LsOp::Const, d->second);
    fail_(fmt::format("unknown name '{}'", name));
  }

  std::string_view s_;
  const std::vector<std::string>& formals_;
  const std::map<std::string, float>& defines_;
  const std::function<void(const std::string&)>& fail_;
  size_t pos_ = 0;
  int depth_ = 0;
  LsExpr out_;
};

class LsysReader {
 public:
  LsysReader(const std::filesystem::path& file) : file_(file) {}

  LSystemSpecies read(const std::string& text) {
    LSystemSpecies out;
    out.name = file_.stem().string();
    int line_no = 0;
    size_t start = 0;
    while (start <= text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      ++line_no;
      line_ = line_no;
      statement(normalise_line(std::string_view(text).substr(start, end - start)), out);
      start = end + 1;
    }
    line_ = std::max(1, static_cast<int>(std::count(text.begin(), text.end(), '\n')) +
                            (text.empty() || text.back() == '\n' ? 0 : 1));  // the last line
    if (!axiom_line_) fail("missing 'axiom = ...'");
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw ParseError(file_, line_, what); }

  void statement(const std::string& line, LSystemSpecies& out) {
    if (line.empty()) return;
    const size_t arrow = line.find("->");
    if (arrow != std::string::npos) return production(line, arrow, out.system);
    if (line.starts_with("define ") || line.starts_with("define\t")) return define(line.substr(7));
    const size_t eq = line.find('=');
    if (eq == std::string::npos)
      fail(fmt::format("expected 'key = value', 'define name = value' or a production 'A -> ...', not '{}'", line));
    const std::string key(trim_blanks(std::string_view(line).substr(0, eq)));
    const std::string value(trim_blanks(std::string_view(line).substr(eq + 1)));
    if (value.empty()) fail(fmt::format("'{}' needs a value", key));
    if (const auto it = seen_.find(key); it != seen_.end())
      fail(fmt::format("'{}' given twice (first on line {})", key, it->second));
    seen_.emplace(key, line_);
    LsTurtle& t = out.system.turtle;
    if (key == "name") {
      out.name = unquote(value);
    } else if (key == "model") {
      if (unquote(value) != "lsystem")
        fail(fmt::format("model must be \"lsystem\" in an L-system file, not {}", value));
    } else if (key == "axiom") {
      axiom_line_ = line_;
      out.system.axiom = axiom(value);
    } else if (key == "iterations") {
      out.system.iterations = static_cast<int>(number(key, value, 0, 64, true));
    } else if (key == "seed") {
      uint64_t seed = 0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), seed);
      if (ec != std::errc() || ptr != value.data() + value.size())
        fail(fmt::format("'seed' must be a non-negative integer, not {}", value));
      out.system.seed = seed;
    } else if (key == "angle") {
      t.angle_deg = number(key, value, -360, 360);
    } else if (key == "step") {
      t.step = number(key, value, -1e6, 1e6);
    } else if (key == "width") {
      t.width = number(key, value, 0, 1e6);
    } else if (key == "width_factor") {
      t.width_factor = number(key, value, 0, 10);
    } else if (key == "unit_m") {
      t.unit_m = number(key, value, 1e-6, 1e3);
      if (t.unit_m <= 0) fail("'unit_m' must be positive");
    } else if (key == "tropism") {
      t.tropism = vector3(key, value);
    } else if (key == "tropism_e") {
      t.tropism_e = number(key, value, -10, 10);
    } else if (key == "leaf_length") {
      t.leaf_length = number(key, value, 0, 1e6);
    } else if (key == "leaf_width") {
      t.leaf_width = number(key, value, 0, 1e6);
    } else if (key == "leaf_shape") {
      const std::optional<LeafShape> shape = leaf_shape_from_name(unquote(value));
      if (!shape) fail(fmt::format("unknown leaf_shape {}", value));
      t.leaf_shape = *shape;
    } else {
      fail(fmt::format("unknown setting '{}'", key));
    }
  }

  std::string unquote(const std::string& v) const {
    if (v.size() >= 2 && v.front() == '"' && v.back() == '"') return v.substr(1, v.size() - 2);
    if (v.find('"') != std::string::npos) fail(fmt::format("unbalanced quotes in {}", v));
    return v;
  }

  float number(const std::string& key, const std::string& value, double lo, double hi, bool integer = false) const {
    const float v = constant(value, key);
    if (integer && v != std::floor(v)) fail(fmt::format("'{}' must be an integer, not {}", key, value));
    if (v < lo || v > hi) fail(fmt::format("'{}' must be in [{}, {}], not {}", key, lo, hi, value));
    return v;
  }

  Vec3 vector3(const std::string& key, const std::string& value) const {
    Vec3 v;
    size_t pos = 0;
    for (int k = 0; k < 3; ++k) {
      if (k > 0) {
        if (pos >= value.size() || value[pos] != ',') fail(fmt::format("'{}' needs three values x, y, z", key));
        ++pos;
      }
      v[k] = expr_at(value, pos, {}).eval({});
    }
    if (trim_blanks(std::string_view(value).substr(pos)).size() != 0)
      fail(fmt::format("'{}' needs three values x, y, z", key));
    if (!is_finite(v) || glm::length(v) > 1e6f) fail(fmt::format("'{}' must be finite", key));
    return v;
  }

  LsExpr expr_at(std::string_view text, size_t& pos, const std::vector<std::string>& formals) const {
    const std::function<void(const std::string&)> f = [this](const std::string& what) { fail(what); };
    LsExpr e = ExprParser(text, formals, defines_, f).parse(pos);
    while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\t')) ++pos;
    return e;
  }

  float constant(std::string_view text, const std::string& what) const {
    size_t pos = 0;
    const LsExpr e = expr_at(text, pos, {});
    if (pos != text.size()) fail(fmt::format("unexpected '{}' after the value of '{}'", text.substr(pos), what));
    const float v = e.eval({});
    if (!std::isfinite(v)) fail(fmt::format("the value of '{}' is not finite", what));
    return v;
  }

  void define(std::string_view rest) {
    const size_t eq = rest.find('=');
    if (eq == std::string_view::npos) fail("expected 'define name = value'");
    const std::string name(trim_blanks(rest.substr(0, eq)));
    if (name.empty() || !is_ident_start(name[0]) ||
        !std::all_of(name.begin(), name.end(), [](char c) { return is_ident_char(c); }))
      fail(fmt::format("'{}' is not a valid name", name));
    if (defines_.count(name)) fail(fmt::format("'{}' defined twice", name));
    defines_[name] = constant(trim_blanks(rest.substr(eq + 1)), name);
  }

  // A word of modules; with `formals`, arguments are expressions over them (a successor),
  // otherwise constants (the axiom).
  std::vector<LsModuleTemplate> modules(std::string_view text, const std::vector<std::string>& formals) const {
    std::vector<LsModuleTemplate> out;
    size_t pos = 0;
    int brackets = 0, braces = 0;
    while (pos < text.size()) {
      const char c = text[pos];
      if (c == ' ' || c == '\t') {
        ++pos;
        continue;
      }
      if (!is_symbol(c)) fail(fmt::format("{} is not a module symbol", show(c)));
      if (out.size() >= 1'000'000) fail("word too long");
      LsModuleTemplate m;
      m.symbol = c;
      brackets += c == '[' ? 1 : c == ']' ? -1 : 0;
      braces += c == '{' ? 1 : c == '}' ? -1 : 0;
      if (brackets < 0) fail("']' without a matching '['");
      if (braces < 0) fail("'}' without a matching '{'");
      ++pos;
      if (pos < text.size() && text[pos] == '(') {
        ++pos;
        for (;;) {
          if (m.args.size() >= static_cast<size_t>(kLsMaxParams))
            fail(fmt::format("module '{}' has more than {} parameters", c, kLsMaxParams));
          m.args.push_back(expr_at(text, pos, formals));
          if (pos < text.size() && text[pos] == ',') {
            ++pos;
            continue;
          }
          if (pos < text.size() && text[pos] == ')') {
            ++pos;
            break;
          }
          fail(fmt::format("expected ',' or ')' in the parameters of '{}'", c));
        }
      }
      out.push_back(std::move(m));
    }
    if (brackets != 0) fail("'[' without a matching ']'");
    if (braces != 0) fail("'{' without a matching '}'");
    return out;
  }

  LsWord axiom(std::string_view text) const {
    LsWord w;
    std::vector<float> values;
    for (const LsModuleTemplate& m : modules(text, {})) {
      values.clear();
      for (const LsExpr& e : m.args) values.push_back(e.eval({}));
      for (const float v : values)
        if (!std::isfinite(v)) fail(fmt::format("a parameter of '{}' in the axiom is not finite", m.symbol));
      w.push(m.symbol, values);
    }
    if (w.size() == 0) fail("the axiom is empty");
    return w;
  }

  void production(const std::string& line, size_t arrow, LSystem& system) {
    std::string_view lhs = std::string_view(line).substr(0, arrow);
    std::string_view rhs = std::string_view(line).substr(arrow + 2);
    if (lhs.ends_with('-')) lhs.remove_suffix(1);  // "-->"
    LsProduction p;
    // Predecessor and formals.
    lhs = trim_blanks(lhs);
    if (lhs.empty() || !is_symbol(lhs[0]) || lhs[0] == '[' || lhs[0] == ']')
      fail("a production needs a predecessor symbol before '->'");
    p.predecessor = lhs[0];
    size_t pos = 1;
    std::vector<std::string> formals;
    if (pos < lhs.size() && lhs[pos] == '(') {
      const size_t close = lhs.find(')', pos);
      if (close == std::string_view::npos) fail("expected ')' closing the formal parameters");
      std::string_view list = lhs.substr(pos + 1, close - pos - 1);
      while (true) {
        const size_t comma = list.find(',');
        const std::string name(trim_blanks(list.substr(0, comma)));
        if (name.empty() || !is_ident_start(name[0]) ||
            !std::all_of(name.begin(), name.end(), [](char ch) { return is_ident_char(ch); }))
          fail(fmt::format("'{}' is not a valid parameter name", name));
        if (std::find(formals.begin(), formals.end(), name) != formals.end())
          fail(fmt::format("parameter '{}' given twice", name));
        if (formals.size() >= static_cast<size_t>(kLsMaxParams))
          fail(fmt::format("more than {} parameters", kLsMaxParams));
        formals.push_back(name);
        if (comma == std::string_view::npos) break;
        list.remove_prefix(comma + 1);
      }
      pos = close + 1;
    }
    p.param_count = static_cast<int>(formals.size());
    const std::string_view after = trim_blanks(lhs.substr(pos));
    if (!after.empty()) {
      if (after[0] != ':') fail(fmt::format("expected ':' or '->' after the predecessor, not '{}'", after));
      const std::string_view cond = trim_blanks(after.substr(1));
      if (cond.empty()) fail("expected a condition (or '*') after ':'");
      if (cond != "*") {
        size_t cpos = 0;
        p.condition = expr_at(cond, cpos, formals);
        if (cpos != cond.size()) fail(fmt::format("unexpected '{}' in the condition", cond.substr(cpos)));
      }
    }
    // Successor and probability: the last ':' (no successor symbol is ':').
    rhs = trim_blanks(rhs);
    const size_t colon = rhs.rfind(':');
    if (colon != std::string_view::npos) {
      const std::string_view prob = trim_blanks(rhs.substr(colon + 1));
      if (prob.empty()) fail("expected a probability after ':'");
      p.probability = constant(prob, "probability");
      if (!(p.probability > 0.0f) || p.probability > 1.0f)
        fail(fmt::format("the probability must be in (0, 1], not {}", prob));
      rhs = trim_blanks(rhs.substr(0, colon));
    }
    p.successor = modules(rhs, formals);
    system.productions.push_back(std::move(p));
  }

  std::filesystem::path file_;
  int line_ = 0;
  int axiom_line_ = 0;
  std::map<std::string, int> seen_;
  std::map<std::string, float> defines_;
};

}  // namespace

LSystemSpecies parse_lsystem(const std::string& text, const std::filesystem::path& file) {
  return LsysReader(file).read(text);
}

AspenGrammarSpecies parse_aspen_grammar(const std::string& text, const std::filesystem::path& file) {
  AspenGrammarSpecies out;
  Params params(file.string(), 1, "the grammar file");
  std::map<std::string, int> seen;
  int line_no = 0;
  size_t start = 0;
  const auto fail = [&](int line, const std::string& what) { throw ParseError(file, line, what); };
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    const std::string line = normalise_line(std::string_view(text).substr(start, end - start));
    start = end + 1;
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) fail(line_no, fmt::format("expected 'key = value', not '{}'", line));
    const std::string key(trim_blanks(std::string_view(line).substr(0, eq)));
    const std::string value(trim_blanks(std::string_view(line).substr(eq + 1)));
    if (key.empty()) fail(line_no, "expected a key before '='");
    if (value.empty()) fail(line_no, fmt::format("'{}' needs a value", key));
    if (const auto it = seen.find(key); it != seen.end())
      fail(line_no, fmt::format("'{}' given twice (first on line {})", key, it->second));
    seen.emplace(key, line_no);
    ParamValue v;
    v.line = line_no;
    const bool quoted = value.size() >= 2 && value.front() == '"' && value.back() == '"';
    if (!quoted && value.find('"') != std::string::npos) fail(line_no, fmt::format("unbalanced quotes in {}", value));
    double x = 0;
    const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), x);
    if (!quoted && ec == std::errc() && ptr == value.data() + value.size()) {
      v.kind = ParamValue::Kind::Real;
      v.real = x;
    } else {
      v.kind = ParamValue::Kind::String;
      v.string = quoted ? value.substr(1, value.size() - 2) : value;
    }
    params.add(key, std::move(v));
  }
  out.name = params.string("name", file.stem().string());
  const std::string model = params.string("model", std::string(AspenGrammarParams::kType));
  if (model != AspenGrammarParams::kType)
    params.fail("model",
                fmt::format("model must be \"{}\" in a grammar file, not \"{}\"", AspenGrammarParams::kType, model));
  std::vector<std::string> warnings;
  out.params = AspenGrammarParams::create(params, warnings);
  return out;
}

}  // namespace sylva

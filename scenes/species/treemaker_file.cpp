#include "scenes/species/treemaker_file.h"

#include "core/input_file.h"

#include "core/error.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace sylva {

namespace {

constexpr int kMaxIterations = 10000;
constexpr int kMaxLevel = 255;
// Probabilities must add up to one within this (the paper's dogwood writes 0.45 + 0.45 + 0.10).
constexpr double kProbabilityTolerance = 1e-3;

enum class Tok { Word, Number, Punct, End };

struct Token {
  Tok kind = Tok::End;
  std::string text;  // word or punctuation character
  double number = 0.0;
  int line = 1;
};

// Figure 6 note 3: "Any kind of spacing is allowed, as long as the curly braces, parentheses, and
// equal signs are correct" — so the text is a stream of words, numbers and { } ( ) = , : tokens.
std::vector<Token> tokenize(const std::string& text, const std::filesystem::path& file) {
  std::vector<Token> out;
  int line = 1;
  size_t i = 0;
  const size_t n = text.size();
  const auto is_digit = [&](size_t k) { return k < n && text[k] >= '0' && text[k] <= '9'; };
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
      ++i;
    } else if (c == '#') {
      while (i < n && text[i] != '\n') ++i;
    } else if (std::string_view("{}()=,:").find(c) != std::string_view::npos) {
      out.push_back(Token{Tok::Punct, std::string(1, c), 0.0, line});
      ++i;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const size_t start = i;
      while (i < n && (std::isalnum(static_cast<unsigned char>(text[i])) || text[i] == '_')) ++i;
      out.push_back(Token{Tok::Word, text.substr(start, i - start), 0.0, line});
    } else if (is_digit(i) || ((c == '-' || c == '+' || c == '.') &&
                               (is_digit(i + 1) || (c != '.' && i + 1 < n && text[i + 1] == '.' && is_digit(i + 2))))) {
      const size_t start = i;
      if (text[i] == '-' || text[i] == '+') ++i;
      while (is_digit(i)) ++i;
      if (i < n && text[i] == '.') {
        ++i;
        while (is_digit(i)) ++i;
      }
      if (i < n && (text[i] == 'e' || text[i] == 'E')) {
        size_t k = i + 1;
        if (k < n && (text[k] == '-' || text[k] == '+')) ++k;
        if (is_digit(k)) {
          i = k;
          while (is_digit(i)) ++i;
        }
      }
      const size_t skip = text[start] == '+' ? 1 : 0;
      double value = 0.0;
      const auto [end, ec] = std::from_chars(text.data() + start + skip, text.data() + i, value);
      if (ec != std::errc() || end != text.data() + i || !std::isfinite(value))
        throw ParseError(file, line, fmt::format("number '{}' is out of range", text.substr(start, i - start)));
      out.push_back(Token{Tok::Number, text.substr(start, i - start), value, line});
    } else {
      const unsigned char u = static_cast<unsigned char>(c);
      throw ParseError(file, line,
                       u >= 0x20 && u < 0x7f ? fmt::format("unexpected character '{}'", c)
                                             : fmt::format("unexpected byte 0x{:02x}", static_cast<int>(u)));
    }
  }
  out.push_back(Token{Tok::End, "", 0.0, line});
  return out;
}

std::string describe(const Token& t) {
  switch (t.kind) {
    case Tok::Word:
      return "'" + t.text + "'";
    case Tok::Number:
      return "the number " + t.text;
    case Tok::Punct:
      return "'" + t.text + "'";
    case Tok::End:
      break;
  }
  return "the end of the file";
}

class Parser {
 public:
  Parser(const std::string& text, const std::filesystem::path& file) : file_(file), toks_(tokenize(text, file)) {}

  TreeMakerTemplate parse() {
    while (peek().kind != Tok::End) section();
    const int last = toks_.back().line;
    if (!seen_.count("iterations")) fail(last, "missing the iterations { i= ... } section");
    if (t_.branches.empty()) fail(last, "a template needs at least one branch rule (§V)");
    if (t_.particles.empty()) fail(last, "a template needs at least one particle (§V)");
    if (t_.leaves.empty()) fail(last, "a template needs at least one leaf definition (§V)");
    double sum = 0.0;
    for (const TreeMakerLeaf& l : t_.leaves) sum += l.p;
    if (std::abs(sum - 1.0) > kProbabilityTolerance)
      fail(last_leaf_line_, fmt::format("the leaf probabilities add up to {:.6g}, not 1 (Figure 6, note 5)", sum));
    std::sort(t_.branches.begin(), t_.branches.end(),
              [](const TreeMakerBranchRule& a, const TreeMakerBranchRule& b) { return a.level < b.level; });
    return std::move(t_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& what) const { throw ParseError(file_, line, what); }

  const Token& peek() const { return toks_[pos_]; }
  const Token& next() {
    const Token& t = toks_[pos_];
    if (t.kind != Tok::End) ++pos_;
    return t;
  }
  bool at_punct(char c) const { return peek().kind == Tok::Punct && peek().text[0] == c; }
  void expect_punct(char c, const std::string& context) {
    const Token& t = next();
    if (t.kind != Tok::Punct || t.text[0] != c)
      fail(t.line, fmt::format("expected '{}' {}, found {}", c, context, describe(t)));
  }

  // A keyword and its '=': returns the keyword token.
  Token keyword(const std::string& section) {
    const Token t = next();
    if (t.kind != Tok::Word)
      fail(t.line, fmt::format("expected a keyword or '}}' in {}, found {}", section, describe(t)));
    expect_punct('=', "after '" + t.text + "'");
    return t;
  }

  double number(const std::string& what) {
    const Token& t = next();
    if (t.kind != Tok::Number) fail(t.line, fmt::format("expected a number for {}, found {}", what, describe(t)));
    return t.number;
  }
  float finite_float(double v, int line, const std::string& what) const {
    if (std::abs(v) > 1e30) fail(line, fmt::format("{} {:g} is out of range", what, v));
    return static_cast<float>(v);
  }
  float number_in(const std::string& what, double lo, double hi) {
    const int line = peek().line;
    const double v = number("'" + what + "='");
    if (v < lo || v > hi) fail(line, fmt::format("'{}=' must be in [{:g}, {:g}], not {:g}", what, lo, hi, v));
    return static_cast<float>(v);
  }
  int integer_in(const std::string& what, int lo, int hi) {
    const int line = peek().line;
    const double v = number("'" + what + "='");
    if (v != std::floor(v) || v < lo || v > hi)
      fail(line, fmt::format("'{}=' must be a whole number in [{}, {}], not {:g}", what, lo, hi, v));
    return static_cast<int>(v);
  }
  // "low to high", or a single number.
  TreeMakerRange range(const std::string& what, double lo = -1e30, double hi = 1e30) {
    const int line = peek().line;
    TreeMakerRange r;
    r.lo = r.hi = finite_float(number("'" + what + "='"), line, "'" + what + "='");
    if (peek().kind == Tok::Word && peek().text == "to") {
      next();
      r.hi = finite_float(number("the end of the '" + what + "=' range after 'to'"), line, "'" + what + "='");
    }
    if (r.lo > r.hi)
      fail(line, fmt::format("'{}=' range goes from {:g} down to {:g} (Figure 6, note 6: minimum to maximum)", what,
                             r.lo, r.hi));
    if (r.lo < lo || r.hi > hi) fail(line, fmt::format("'{}=' must lie in [{:g}, {:g}]", what, lo, hi));
    return r;
  }
  Vec3 vec3(const std::string& what) {
    const int line = peek().line;
    Vec3 v;
    for (int k = 0; k < 3; ++k) {
      if (k > 0) expect_punct(',', "between the coordinates of '" + what + "='");
      v[k] = finite_float(number("'" + what + "='"), line, "'" + what + "='");
    }
    return v;
  }
  int color_ref(const std::string& what) {
    const Token& t = next();
    if (t.kind != Tok::Word) fail(t.line, fmt::format("expected a color name for '{}=', found {}", what, describe(t)));
    for (size_t i = 0; i < t_.colors.size(); ++i)
      if (t_.colors[i].name == t.text) return static_cast<int>(i);
    fail(t.line, fmt::format("unknown color '{}' (define it in a color {{ }} section before use)", t.text));
  }
  void once(std::set<std::string>& seen, const Token& key, const std::string& section) {
    if (!seen.insert(key.text).second) fail(key.line, fmt::format("'{}=' is repeated in {}", key.text, section));
  }
  void require(const std::set<std::string>& seen, const std::string& key, int line, const std::string& section) {
    if (!seen.count(key)) fail(line, fmt::format("{} is missing '{}='", section, key));
  }
  [[noreturn]] void unknown(const Token& key, const std::string& section, const std::string& expected) const {
    fail(key.line, fmt::format("unknown keyword '{}' in {} (expected {})", key.text, section, expected));
  }

  void section() {
    const Token name = next();
    if (name.kind != Tok::Word)
      fail(name.line, fmt::format("expected a section name (iterations, gravity, light, color, branch, particle or "
                                  "leaf), found {}",
                                  describe(name)));
    const std::string& s = name.text;
    if (s != "iterations" && s != "gravity" && s != "light" && s != "color" && s != "branch" && s != "particle" &&
        s != "leaf")
      fail(name.line, fmt::format("unknown section '{}' (expected iterations, gravity, light, color, branch, particle "
                                  "or leaf)",
                                  s));
    if ((s == "iterations" || s == "gravity" || s == "light") && !seen_.insert(s).second)
      fail(name.line, fmt::format("the {} section is repeated", s));
    expect_punct('{', "after '" + s + "'");
    if (s == "iterations") return iterations(name.line);
    if (s == "gravity") return gravity(name.line);
    if (s == "light") return light();
    if (s == "color") return color(name.line);
    if (s == "branch") return branch(name.line);
    if (s == "particle") return particle();
    return leaf(name.line);
  }

  void iterations(int line) {
    std::set<std::string> seen;
    while (!at_punct('}')) {
      const Token k = keyword("iterations");
      if (k.text != "i") unknown(k, "iterations", "i=");
      once(seen, k, "iterations");
      t_.iterations = integer_in("i", 1, kMaxIterations);
    }
    require(seen, "i", line, "iterations");
    next();
  }

  void gravity(int line) {
    std::set<std::string> seen;
    while (!at_punct('}')) {
      const Token k = keyword("gravity");
      if (k.text != "g") unknown(k, "gravity", "g=");
      once(seen, k, "gravity");
      t_.gravity = number_in("g", -1e6, 1e6);
    }
    require(seen, "g", line, "gravity");
    next();
  }

  void light() {
    std::set<std::string> seen;
    while (!at_punct('}')) {
      const Token k = keyword("light");
      float* target = k.text == "ambient"   ? &t_.light.ambient
                      : k.text == "lambert" ? &t_.light.lambert
                      : k.text == "height"  ? &t_.light.height
                      : k.text == "radius"  ? &t_.light.radius
                      : k.text == "angle"   ? &t_.light.angle
                                            : nullptr;
      if (target == nullptr) unknown(k, "light", "ambient=, lambert=, height=, radius= or angle=");
      once(seen, k, "light");
      *target = number_in(k.text, -1e6, 1e6);
    }
    next();
  }

  // color { name= r,g,b }: one or more definitions.
  void color(int line) {
    bool any = false;
    while (!at_punct('}')) {
      const Token k = keyword("color");
      for (const TreeMakerColor& c : t_.colors)
        if (c.name == k.text) fail(k.line, fmt::format("color '{}' is already defined", k.text));
      const Vec3 rgb = vec3(k.text);
      if (rgb.x < 0 || rgb.y < 0 || rgb.z < 0 || std::max({rgb.x, rgb.y, rgb.z}) <= 0)
        fail(k.line, fmt::format("color '{}' needs non-negative red, green, blue weights, not all zero", k.text));
      t_.colors.push_back(TreeMakerColor{k.text, rgb});
      any = true;
    }
    if (!any) fail(line, "empty color section (expected name= red,green,blue)");
    next();
  }

  void branch(int line) {
    if (!t_.particles.empty()) fail(line, "branch rules must come before the particles (Figure 6, note 4)");
    TreeMakerBranchRule rule;
    std::set<std::string> seen;
    while (!at_punct('}')) {
      if (at_punct('(')) {
        next();
        rule.choices.push_back(triplet());
        continue;
      }
      const Token k = keyword("branch");
      once(seen, k, "branch");
      if (!rule.choices.empty()) fail(k.line, fmt::format("'{}=' must come before the (p= ...) triplets", k.text));
      if (k.text == "level")
        rule.level = integer_in("level", 1, kMaxLevel);
      else if (k.text == "number")
        rule.number = range("number", 0.0, 1e6);
      else
        unknown(k, "branch", "level=, number= or a (p= angle= dir= factor=) triplet");
    }
    const int close = peek().line;
    next();
    require(seen, "level", close, "branch");
    require(seen, "number", close, "branch");
    if (rule.choices.empty()) fail(close, "branch needs at least one (p= angle= dir= factor=) triplet");
    double sum = 0.0;
    for (const TreeMakerBranchChoice& c : rule.choices) sum += c.p;
    if (std::abs(sum - 1.0) > kProbabilityTolerance)
      fail(line, fmt::format("the probabilities of branch level {} add up to {:.6g}, not 1 (Figure 6, note 5)",
                             rule.level, sum));
    for (const TreeMakerBranchRule& r : t_.branches)
      if (r.level == rule.level) fail(line, fmt::format("branch level {} is defined twice", rule.level));
    t_.branches.push_back(std::move(rule));
  }

  TreeMakerBranchChoice triplet() {
    TreeMakerBranchChoice c;
    std::set<std::string> seen;
    while (!at_punct(')')) {
      if (peek().kind == Tok::End || at_punct('}')) fail(peek().line, "expected ')' to close the (p= ...) triplet");
      const Token k = keyword("the (p= ...) triplet");
      once(seen, k, "the triplet");
      if (k.text == "p")
        c.p = number_in("p", 0.0, 1.0);
      else if (k.text == "angle")
        c.angle_deg = range("angle");
      else if (k.text == "dir")
        c.dir_deg = range("dir");
      else if (k.text == "factor")
        c.factor = range("factor", 0.0, 1e6);
      else
        unknown(k, "the (p= ...) triplet", "p=, angle=, dir= or factor=");
    }
    const int close = peek().line;
    next();
    for (const char* key : {"p", "angle", "dir", "factor"}) require(seen, key, close, "the triplet");
    return c;
  }

  void particle() {
    TreeMakerParticle p;
    std::set<std::string> seen;
    while (!at_punct('}')) {
      const Token k = keyword("particle");
      once(seen, k, "particle");
      if (k.text == "pos") {
        p.pos = vec3("pos");
      } else if (k.text == "mag") {
        p.mag = range("mag", 0.0, 1e30);
      } else if (k.text == "dir") {
        p.dir = vec3("dir");
        if (glm::length(p.dir) <= 0.0f) fail(k.line, "'dir=' must not be the zero vector");
        if (at_punct(':')) {
          next();
          p.max_dev_deg = number_in("dir=...:maxdev_angle", 0.0, 180.0);
        }
      } else if (k.text == "acc") {
        p.acc = number_in("acc", -1e30, 1e30);
      } else if (k.text == "growth") {
        p.growth = number_in("growth", 0.0, 1e30);
      } else if (k.text == "age") {
        p.age = number_in("age", -1e30, 1e30);
      } else if (k.text == "color") {
        p.color = color_ref("color");
      } else if (k.text == "brightness") {
        p.brightness = range("brightness", 0.0, 1.0);
      } else {
        unknown(k, "particle", "pos=, mag=, dir=, acc=, growth=, age=, color= or brightness=");
      }
    }
    const int close = peek().line;
    next();
    require(seen, "mag", close, "particle");
    require(seen, "color", close, "particle");
    t_.particles.push_back(p);
  }

  void leaf(int line) {
    TreeMakerLeaf l;
    std::set<std::string> seen;
    int color = -1;
    TreeMakerRange brightness{1.0f, 1.0f};
    while (!at_punct('}')) {
      const Token k = keyword("leaf");
      if (k.text == "p" || k.text == "coord" || k.text == "out" || k.text == "up") once(seen, k, "leaf");
      if (k.text == "p") {
        l.p = number_in("p", 0.0, 1.0);
      } else if (k.text == "coord") {
        const Token& v = next();
        if (v.kind != Tok::Word || (v.text != "limb" && v.text != "leaf"))
          fail(v.line, fmt::format("'coord=' must be limb or leaf, not {}", describe(v)));
        l.coord = v.text == "limb" ? TreeMakerCoord::Limb : TreeMakerCoord::Leaf;
      } else if (k.text == "out") {
        l.out_deg = number_in("out", 0.0, 180.0);
      } else if (k.text == "up") {
        l.up_deg = number_in("up", 0.0, 180.0);
      } else if (k.text == "color") {
        color = color_ref("color");
      } else if (k.text == "brightness") {
        brightness = range("brightness", 0.0, 1.0);
      } else if (k.text == "tri" || k.text == "ln") {
        if (color < 0) fail(k.line, fmt::format("'{}=' needs a color= before it in the leaf", k.text));
        TreeMakerElement e;
        e.color = color;
        e.brightness = brightness;
        const int points = k.text == "tri" ? 3 : 2;
        for (int i = 0; i < points; ++i) e.points.push_back(vec3(k.text));
        l.elements.push_back(std::move(e));
      } else {
        unknown(k, "leaf", "p=, coord=, out=, up=, color=, brightness=, tri= or ln=");
      }
    }
    const int close = peek().line;
    next();
    require(seen, "p", close, "leaf");
    if (l.elements.empty()) fail(close, "leaf needs at least one tri= or ln= element");
    last_leaf_line_ = line;
    t_.leaves.push_back(std::move(l));
  }

  std::filesystem::path file_;
  std::vector<Token> toks_;
  size_t pos_ = 0;
  TreeMakerTemplate t_;
  std::set<std::string> seen_;
  int last_leaf_line_ = 0;
};

}  // namespace

TreeMakerTemplate parse_treemaker_template(const std::string& text, const std::filesystem::path& file) {
  return Parser(text, file).parse();
}

TreeMakerTemplate load_treemaker_template(const std::filesystem::path& file) {
  return parse_treemaker_template(read_input_file(file, kMaxSpeciesFileBytes, "template file"), file);
}

}  // namespace sylva

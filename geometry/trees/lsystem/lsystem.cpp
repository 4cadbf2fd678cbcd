#include "geometry/trees/lsystem/lsystem.h"

#include "core/error.h"
#include "core/rng.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace sylva {

namespace {

int stack_effect(LsOp op) {
  switch (op) {
    case LsOp::Const:
    case LsOp::Param:
      return 1;
    case LsOp::Neg:
    case LsOp::Not:
    case LsOp::Sqrt:
    case LsOp::Abs:
    case LsOp::Floor:
    case LsOp::Sin:
    case LsOp::Cos:
      return 0;
    default:
      return -1;
  }
}

int operand_count(LsOp op) {
  const int effect = stack_effect(op);
  return effect == 1 ? 0 : effect == 0 ? 1 : 2;
}

}  // namespace

bool validate_ls_expr(const LsExpr& expr, int param_count) {
  if (expr.code.empty()) return true;
  int depth = 0;
  for (const LsInstr& in : expr.code) {
    if (static_cast<int>(in.op) > static_cast<int>(LsOp::Max)) return false;
    if (in.op == LsOp::Param && in.index >= param_count) return false;
    if (depth < operand_count(in.op)) return false;
    depth += stack_effect(in.op);
    if (depth > kLsMaxStack) return false;
  }
  return depth == 1;
}

float LsExpr::eval(std::span<const float> params) const {
  if (code.empty()) return 1.0f;
  std::array<float, kLsMaxStack> s;
  int n = 0;
  for (const LsInstr& in : code) {
    switch (in.op) {
      case LsOp::Const:
        s[n++] = in.value;
        continue;
      case LsOp::Param:
        s[n++] = params[in.index];
        continue;
      case LsOp::Neg:
        s[n - 1] = -s[n - 1];
        continue;
      case LsOp::Not:
        s[n - 1] = s[n - 1] == 0.0f ? 1.0f : 0.0f;
        continue;
      case LsOp::Sqrt:
        s[n - 1] = std::sqrt(s[n - 1]);
        continue;
      case LsOp::Abs:
        s[n - 1] = std::abs(s[n - 1]);
        continue;
      case LsOp::Floor:
        s[n - 1] = std::floor(s[n - 1]);
        continue;
      case LsOp::Sin:
        s[n - 1] = std::sin(radians(s[n - 1]));
        continue;
      case LsOp::Cos:
        s[n - 1] = std::cos(radians(s[n - 1]));
        continue;
      default:
        break;
    }
    const float b = s[--n];
    float& a = s[n - 1];
    switch (in.op) {
      case LsOp::Add:
        a = a + b;
        break;
      case LsOp::Sub:
        a = a - b;
        break;
      case LsOp::Mul:
        a = a * b;
        break;
      case LsOp::Div:
        a = a / b;
        break;
      case LsOp::Pow:
        a = std::pow(a, b);
        break;
      case LsOp::Lt:
        a = a < b ? 1.0f : 0.0f;
        break;
      case LsOp::Le:
        a = a <= b ? 1.0f : 0.0f;
        break;
      case LsOp::Gt:
        a = a > b ? 1.0f : 0.0f;
        break;
      case LsOp::Ge:
        a = a >= b ? 1.0f : 0.0f;
        break;
      case LsOp::Eq:
        a = a == b ? 1.0f : 0.0f;
        break;
      case LsOp::Ne:
        a = a != b ? 1.0f : 0.0f;
        break;
      case LsOp::And:
        a = (a != 0.0f && b != 0.0f) ? 1.0f : 0.0f;
        break;
      case LsOp::Or:
        a = (a != 0.0f || b != 0.0f) ? 1.0f : 0.0f;
        break;
      case LsOp::Min:
        a = std::min(a, b);
        break;
      case LsOp::Max:
        a = std::max(a, b);
        break;
      default:
        break;
    }
  }
  return s[0];
}

void LsWord::push(char symbol, std::span<const float> values) {
  symbols.push_back(symbol);
  first_param.push_back(static_cast<uint32_t>(params.size()));
  param_count.push_back(static_cast<uint8_t>(values.size()));
  params.insert(params.end(), values.begin(), values.end());
}

LsWord make_ls_word(std::string_view symbols) {
  LsWord w;
  for (const char c : symbols) w.push(c);
  return w;
}

std::string ls_word_string(const LsWord& word) {
  std::string out;
  out.reserve(word.size());
  for (size_t i = 0; i < word.size(); ++i) {
    out += word.symbols[i];
    const std::span<const float> p = word.params_of(i);
    if (p.empty()) continue;
    out += '(';
    for (size_t k = 0; k < p.size(); ++k) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%s%.6g", k ? "," : "", static_cast<double>(p[k]));
      out += buf;
    }
    out += ')';
  }
  return out;
}

// ABOP §1.3 (parallel rewriting), §1.7 (stochastic productions), §1.10 (parametric productions).
LsWord expand_lsystem(const LSystem& system, uint64_t seed, size_t max_modules) {
  for (const LsProduction& p : system.productions) {
    const std::string who = std::string("L-system production for '") + p.predecessor + "'";
    if (p.param_count < 0 || p.param_count > kLsMaxParams || !validate_ls_expr(p.condition, p.param_count))
      throw Error(who + " has a malformed condition");
    if (!(p.probability > 0.0f) || !std::isfinite(p.probability)) throw Error(who + " needs a positive probability");
    for (const LsModuleTemplate& t : p.successor)
      if (t.args.size() > static_cast<size_t>(kLsMaxParams) ||
          !std::all_of(t.args.begin(), t.args.end(),
                       [&](const LsExpr& e) { return !e.code.empty() && validate_ls_expr(e, p.param_count); }))
        throw Error(who + " has a malformed successor");
  }
  std::array<std::vector<uint32_t>, 256> by_symbol;
  for (size_t i = 0; i < system.productions.size(); ++i)
    by_symbol[static_cast<unsigned char>(system.productions[i].predecessor)].push_back(static_cast<uint32_t>(i));

  LsWord current = system.axiom, next;
  std::vector<uint32_t> candidates;
  std::array<float, kLsMaxParams> values{};
  const auto too_long = [&](int iteration) {
    return Error("L-system too long: iteration " + std::to_string(iteration) + " would exceed " +
                 std::to_string(max_modules) + " modules (lower the iterations)");
  };
  if (current.size() > max_modules) throw too_long(0);
  for (int iteration = 1; iteration <= system.iterations; ++iteration) {
    next.symbols.clear();
    next.first_param.clear();
    next.param_count.clear();
    next.params.clear();
    for (size_t m = 0; m < current.size(); ++m) {
      const char symbol = current.symbols[m];
      const std::span<const float> actual = current.params_of(m);
      candidates.clear();
      float total = 0;
      for (const uint32_t pi : by_symbol[static_cast<unsigned char>(symbol)]) {
        const LsProduction& p = system.productions[pi];
        if (p.param_count != static_cast<int>(actual.size())) continue;
        if (p.condition.eval(actual) == 0.0f) continue;
        candidates.push_back(pi);
        total += p.probability;
      }
      if (candidates.empty()) {
        next.push(symbol, actual);
      } else {
        uint32_t chosen = candidates.front();
        if (candidates.size() > 1) {
          Pcg32 rng(hash_ids(system.seed, seed, static_cast<uint64_t>(iteration), static_cast<uint64_t>(m)));
          float u = rng.uniform() * total;
          for (const uint32_t pi : candidates) {
            chosen = pi;
            u -= system.productions[pi].probability;
            if (u < 0.0f) break;
          }
        }
        for (const LsModuleTemplate& t : system.productions[chosen].successor) {
          for (size_t k = 0; k < t.args.size(); ++k) {
            values[k] = t.args[k].eval(actual);
            if (!std::isfinite(values[k]))
              throw Error(std::string("L-system parameter of module '") + t.symbol + "' became " +
                          (std::isnan(values[k]) ? "NaN" : "infinite") + " at iteration " + std::to_string(iteration));
          }
          next.push(t.symbol, std::span<const float>(values.data(), t.args.size()));
        }
      }
      if (next.size() > max_modules) throw too_long(iteration);
    }
    std::swap(current, next);
  }
  return current;
}

namespace {

struct TurtleState {
  Vec3 pos{0, 0, 0};
  Vec3 h{0, 0, 1}, l{-1, 0, 0}, u{0, -1, 0};  // heading, left, up: h × l = u (ABOP §1.5)
  float width = 0;
  int stem = -1;         // stem being drawn in this scope, -1 before the first F
  int branch_from = -1;  // stem current when this scope's bracket opened
};

struct StemBuild {
  int parent = -1;
  int level = 0;
  float offset = 0;
  std::vector<Vec3> positions;
  std::vector<Frame> frames;
  std::vector<float> radius;
  std::vector<float> arc;
};

// Rotates a towards b by `angle` in their plane (a, b orthonormal): returns the new a and b.
void rotate_pair(Vec3& a, Vec3& b, float angle_rad) {
  const float c = std::cos(angle_rad), s = std::sin(angle_rad);
  const Vec3 na = a * c + b * s;
  const Vec3 nb = b * c - a * s;
  a = na;
  b = nb;
}

Vec3 rotate_about(const Vec3& v, const Vec3& axis, float angle_rad) {
  const float c = std::cos(angle_rad), s = std::sin(angle_rad);
  return v * c + glm::cross(axis, v) * s + axis * (glm::dot(axis, v) * (1.0f - c));
}

class Turtle {
 public:
  explicit Turtle(const LsTurtle& t) : t_(t) { state_.width = t.width; }

  TreeModel run(const LsWord& word) {
    for (size_t i = 0; i < word.size(); ++i) step(word.symbols[i], word.params_of(i));
    if (!stack_.empty()) throw Error("L-system word has " + std::to_string(stack_.size()) + " unmatched '['");
    if (!polygons_.empty()) throw Error("L-system word has an unmatched '{'");
    return finish();
  }

 private:
  float arg_or(std::span<const float> p, float fallback) const { return p.empty() ? fallback : p[0]; }

  void step(char c, std::span<const float> p) {
    const float delta = radians(arg_or(p, t_.angle_deg));
    TurtleState& s = state_;
    switch (c) {
      case 'F':
        forward(arg_or(p, t_.step), true);
        break;
      case 'f':
        forward(arg_or(p, t_.step), false);
        break;
      case '+':
        rotate_pair(s.h, s.l, delta);
        break;  // turn left about U
      case '-':
        rotate_pair(s.h, s.l, -delta);
        break;  // turn right
      case '&':
        rotate_pair(s.h, s.u, -delta);
        break;  // pitch down about L
      case '^':
        rotate_pair(s.h, s.u, delta);
        break;  // pitch up
      case '\\':
        rotate_pair(s.l, s.u, delta);
        break;  // roll left about H
      case '/':
        rotate_pair(s.l, s.u, -delta);
        break;  // roll right
      case '|':
        s.h = -s.h, s.l = -s.l;
        break;  // turn around about U
      case '$':
        roll_to_horizontal();
        break;
      case '!':
        s.width = p.empty() ? s.width * t_.width_factor : p[0];
        break;
      case '[':
        stack_.push_back(s);
        s.branch_from = s.stem >= 0 ? s.stem : s.branch_from;
        s.stem = -1;
        break;
      case ']':
        if (stack_.empty()) throw Error("L-system word has an unmatched ']'");
        s = stack_.back();
        stack_.pop_back();
        break;
      case '~':
        add_leaf(arg_or(p, 1.0f));
        break;
      case '{':
        polygons_.push_back({s.pos});
        break;
      case '}':
        close_polygon();
        break;
      case '.':
        if (!polygons_.empty()) polygons_.back().push_back(s.pos);
        break;
      default:
        break;  // other symbols (A, X, ', ...) do not move the turtle
    }
  }

  // ABOP §1.5 '$': roll so that L is horizontal (L = V × H / |V × H|, U = H × L).
  void roll_to_horizontal() {
    TurtleState& s = state_;
    const Vec3 lh = glm::cross(Vec3(0, 0, 1), s.h);
    const float len = glm::length(lh);
    if (len < 1e-6f) return;
    s.l = lh / len;
    s.u = glm::cross(s.h, s.l);
  }

  void forward(float length, bool draw) {
    TurtleState& s = state_;
    const Vec3 start = s.pos;
    s.pos += s.h * length;
    if (!polygons_.empty()) {
      polygons_.back().push_back(s.pos);
      return;
    }
    if (!draw) {
      s.branch_from = s.stem >= 0 ? s.stem : s.branch_from;
      s.stem = -1;
      return;
    }
    if (s.stem < 0) {
      s.stem = static_cast<int>(stems_.size());
      StemBuild b;
      b.parent = s.branch_from;
      if (b.parent >= 0) {
        const StemBuild& parent = stems_[static_cast<size_t>(b.parent)];
        b.level = std::min(parent.level + 1, 255);
        b.offset = parent.arc.empty() ? 0.0f : parent.arc.back();
      }
      push_section(b, start, s.h, 0.0f);
      stems_.push_back(std::move(b));
    }
    StemBuild& b = stems_[static_cast<size_t>(s.stem)];
    push_section(b, s.pos, s.h, b.arc.back() + std::abs(length));
    tropism();
  }

  void push_section(StemBuild& b, const Vec3& p, const Vec3& dir, float arc) {
    const TurtleState& s = state_;
    b.positions.push_back(p);
    b.frames.push_back(Frame{s.l, s.u, dir});
    b.radius.push_back(0.5f * std::abs(s.width));
    b.arc.push_back(arc);
  }

  // ABOP §2.2: H turns towards T about H × T by e·|H × T|.
  void tropism() {
    if (t_.tropism_e == 0.0f) return;
    TurtleState& s = state_;
    const Vec3 axis = glm::cross(s.h, t_.tropism);
    const float len = glm::length(axis);
    if (len < 1e-7f) return;
    const float angle = t_.tropism_e * len;
    const Vec3 a = axis / len;
    s.h = glm::normalize(rotate_about(s.h, a, angle));
    s.l = glm::normalize(rotate_about(s.l, a, angle));
    s.u = glm::cross(s.h, s.l);
  }

  int leaf_stem() const { return state_.stem >= 0 ? state_.stem : state_.branch_from; }

  void add_leaf(float scale) {
    const TurtleState& s = state_;
    leaves_.push_back({s.pos, Frame{s.l, s.u, s.h}, t_.leaf_length * scale, t_.leaf_width * scale, leaf_stem()});
  }

  // A polygon becomes a leaf quad in its plane: from its first vertex (the petiole end) towards
  // its farthest vertex, as wide as its extent across that direction.
  void close_polygon() {
    if (polygons_.empty()) throw Error("L-system word has an unmatched '}'");
    const std::vector<Vec3> v = std::move(polygons_.back());
    polygons_.pop_back();
    if (v.size() < 3) return;
    Vec3 normal(0);
    for (size_t i = 0; i < v.size(); ++i) {  // Newell's method
      const Vec3& a = v[i];
      const Vec3& b = v[(i + 1) % v.size()];
      normal += Vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    Vec3 far = v[0];
    for (const Vec3& q : v)
      if (glm::length(q - v[0]) > glm::length(far - v[0])) far = q;
    const float length = glm::length(far - v[0]);
    if (length < 1e-7f || glm::length(normal) < 1e-12f) return;
    const Vec3 z = (far - v[0]) / length;
    Vec3 y = normal - z * glm::dot(normal, z);
    if (glm::length(y) < 1e-7f) return;
    y = glm::normalize(y);
    const Vec3 x = glm::cross(y, z);
    float lo = 0, hi = 0;
    for (const Vec3& q : v) {
      const float across = glm::dot(q - v[0], x);
      lo = std::min(lo, across);
      hi = std::max(hi, across);
    }
    if (hi - lo < 1e-7f) return;
    leaves_.push_back({v[0] + x * (0.5f * (lo + hi)), Frame{x, y, z}, length, hi - lo, leaf_stem()});
  }

  TreeModel finish() {
    TreeModel m;
    const float k = t_.unit_m;
    for (const StemBuild& b : stems_) {
      TreeStems& st = m.stems;
      st.level.push_back(static_cast<uint8_t>(b.level));
      st.parent.push_back(b.parent);
      st.clone_of.push_back(-1);
      st.first_section.push_back(static_cast<uint32_t>(m.sections.size()));
      st.section_count.push_back(static_cast<uint32_t>(b.positions.size()));
      st.length_m.push_back(b.arc.back() * k);
      st.base_radius_m.push_back(b.radius.front() * k);
      st.offset_m.push_back(b.offset * k);
      st.lobes.push_back(0);
      st.lobe_depth.push_back(0.0f);
      for (size_t i = 0; i < b.positions.size(); ++i) {
        m.sections.positions.push_back(b.positions[i] * k);
        m.sections.frames.push_back(b.frames[i]);
        m.sections.radius_m.push_back(b.radius[i] * k);
        m.sections.arc_m.push_back(b.arc[i] * k);
      }
    }
    for (const Leaf& leaf : leaves_) {
      m.leaves.positions.push_back(leaf.pos * k);
      m.leaves.frames.push_back(leaf.frame);
      m.leaves.length_m.push_back(std::abs(leaf.length) * k);
      m.leaves.width_m.push_back(std::abs(leaf.width) * k);
      m.leaves.shapes.push_back(t_.leaf_shape);
      m.leaves.stem.push_back(leaf.stem);
    }
    return m;
  }

  struct Leaf {
    Vec3 pos;
    Frame frame;
    float length, width;
    int stem;
  };

  const LsTurtle& t_;
  TurtleState state_;
  std::vector<TurtleState> stack_;
  std::vector<std::vector<Vec3>> polygons_;
  std::vector<StemBuild> stems_;
  std::vector<Leaf> leaves_;
};

}  // namespace

LSystem LSystem::create(const Params& params, std::vector<std::string>&) {
  params.fail("model", "an L-system is written as a .lsys file with its axiom and productions (docs/lsystems.md)");
}

TreeModel interpret_lsystem(const LsWord& word, const LsTurtle& turtle) { return Turtle(turtle).run(word); }

TreeModel make_lsystem_tree(const LSystem& system, uint64_t seed) {
  return interpret_lsystem(expand_lsystem(system, seed), system.turtle);
}

}  // namespace sylva

#pragma once
// Bracketed, stochastic, parametric L-systems and their 3-D turtle (Prusinkiewicz & Lindenmayer,
// "The Algorithmic Beauty of Plants" (ABOP) §1.3–1.10, §2.1–2.2; the aspen thesis, seed 002,
// Chapter 4). Plain data in, plain data out: `expand_lsystem` rewrites the axiom in parallel,
// `interpret_lsystem` walks the word with a turtle into a TreeModel. The text format that builds
// these structs is scenes/species/lsystem_file.h; the conventions are docs/lsystems.md.

#include "core/params.h"
#include "geometry/leaf_shape.h"
#include "geometry/trees/tree_model.h"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

// An arithmetic expression over a module's parameters, as postfix code. Comparisons and logic
// yield 1 or 0; a value is true when it is not 0. Angles of sin/cos are in degrees (as in cpfg).
enum class LsOp : uint8_t {
  Const,  // push value
  Param,  // push the index-th parameter of the predecessor
  Neg,
  Not,
  Add,
  Sub,
  Mul,
  Div,
  Pow,
  Lt,
  Le,
  Gt,
  Ge,
  Eq,
  Ne,
  And,
  Or,
  Sqrt,
  Abs,
  Floor,
  Sin,
  Cos,
  Min,
  Max
};

struct LsInstr {
  LsOp op = LsOp::Const;
  uint8_t index = 0;
  float value = 0;
};

inline constexpr int kLsMaxStack = 64;   // deepest evaluation stack an expression may need
inline constexpr int kLsMaxParams = 16;  // most parameters one module may carry

struct LsExpr {
  std::vector<LsInstr> code;  // empty: the constant 1 (a production without condition)

  static LsExpr constant(float value) { return LsExpr{{LsInstr{LsOp::Const, 0, value}}}; }
  static LsExpr parameter(int index) { return LsExpr{{LsInstr{LsOp::Param, static_cast<uint8_t>(index), 0}}}; }
  // Evaluates with the given actual parameters. Precondition: `validate_ls_expr` accepted it for
  // this parameter count.
  float eval(std::span<const float> params) const;
};

// Whether the code is well formed for `param_count` parameters (stack never under- or
// overflows, ends with exactly one value, parameter indices in range).
bool validate_ls_expr(const LsExpr& expr, int param_count);

// A word: modules (symbol + parameters) as a structure of arrays.
struct LsWord {
  std::vector<char> symbols;
  std::vector<uint32_t> first_param;
  std::vector<uint8_t> param_count;
  std::vector<float> params;

  size_t size() const { return symbols.size(); }
  std::span<const float> params_of(size_t i) const { return {params.data() + first_param[i], param_count[i]}; }
  void push(char symbol, std::span<const float> values = {});
};

// A word of parameterless modules, one per character ("F[+F]F").
LsWord make_ls_word(std::string_view symbols);

// The word as text: "F(1,0.5)[+F]"; parameters printed with up to 6 significant digits.
std::string ls_word_string(const LsWord& word);

struct LsModuleTemplate {
  char symbol = 'F';
  std::vector<LsExpr> args;
};

// pred(params) : condition -> successor : probability. Among the productions whose predecessor
// symbol and parameter count match a module and whose condition holds, one is chosen with
// probability proportional to `probability`; a module no production matches is copied.
struct LsProduction {
  char predecessor = 'F';
  int param_count = 0;
  LsExpr condition;
  std::vector<LsModuleTemplate> successor;
  float probability = 1;
};

// How the turtle reads symbols (docs/lsystems.md has the table). Lengths and widths are in turtle
// units; `unit_m` converts them to metres.
struct LsTurtle {
  float angle_deg = 25.7f;    // δ of + - & ^ \ / without argument
  float step = 1;             // F and f without argument
  float width = 0.1f;         // initial stem diameter
  float width_factor = 0.7f;  // ! without argument multiplies the diameter by this
  float unit_m = 1;           // metres per turtle unit
  Vec3 tropism{0, 0, -1};     // ABOP §2.2 tropism vector T (tree space, Z up)
  float tropism_e = 0;        // susceptibility e: each F bends H towards T by e·|H × T| radians
  float leaf_length = 0.5f;   // ~ draws a leaf this long (× its argument, if any)
  float leaf_width = 0.25f;
  LeafShape leaf_shape = LeafShape::Oval;
};

struct LSystem {
  // Registry entry (geometry/trees/tree_models.h). L-systems are written as .lsys files
  // (scenes/species/lsystem_file.h); `create` from a table of parameters reports that.
  static constexpr std::string_view kType = "lsystem";
  static LSystem create(const Params& params, std::vector<std::string>& warnings);

  LsWord axiom;
  std::vector<LsProduction> productions;
  int iterations = 0;
  uint64_t seed = 0;  // the file's seed: with the tree seed it selects the stochastic choices
  LsTurtle turtle;
};

// Longest word expansion may build before it gives up with a clear error.
inline constexpr size_t kLsDefaultModuleBudget = 4'000'000;

// Rewrites the axiom `iterations` times in parallel (ABOP §1.3). Stochastic choices come from
// hash_ids(system.seed, seed, iteration, module index), so the result is deterministic and
// independent of evaluation order. Throws sylva::Error ("L-system too long: ...") when a word
// would exceed `max_modules`, or when a parameter becomes NaN or infinite.
LsWord expand_lsystem(const LSystem& system, uint64_t seed, size_t max_modules = kLsDefaultModuleBudget);

// The 3-D turtle (ABOP §1.5, §2.2). Starts at the origin heading up (+Z) with its left vector
// along −X (so + turns towards −X, seen from −Y). Each unbroken run of F in one bracket scope is one
// stem of cross-sections (radius = diameter / 2); a stem begun inside a bracket is a child of the
// stem the bracket branched from. `~` adds a leaf; `{ . }` polygons become leaves spanning their
// vertices. Throws sylva::Error on an unmatched ] or }.
TreeModel interpret_lsystem(const LsWord& word, const LsTurtle& turtle);

// Expands and interprets. Pure: the same system and seed give a bit-identical model.
TreeModel make_lsystem_tree(const LSystem& system, uint64_t seed);

// The registry's generator: the options (wind, quality) do not apply to L-systems.
inline TreeModel make_tree(const LSystem& system, uint64_t seed, const TreeOptions&) {
  return make_lsystem_tree(system, seed);
}

}  // namespace sylva

#pragma once
// Text formats of the L-system models (docs/lsystems.md has the full description).
//
// L-system files (.lsys), one statement per line, `#` starts a comment:
//
//   name = "ABOP bush"            # optional
//   angle = 22.5                  # δ, degrees
//   iterations = 7
//   seed = 1                      # with the tree seed, selects the stochastic choices
//   step = 1    width = 0.1 ...   # turtle settings: step, width, width_factor, unit_m,
//                                 #   tropism = x, y, z, tropism_e, leaf_length, leaf_width,
//                                 #   leaf_shape (a LeafShape name)
//   define r1 = 0.9               # a named constant usable in expressions
//   axiom = A(1, 10)
//   A(l, w) : l > 0.1 -> !(w)F(l)[&(45)B(l*r1, w*0.7)]/(137.5)A(l*r1, w*0.7)
//   F -> F[+F]F[-F]F : 0.33       # a production chosen with probability 0.33
//
// A production is `predecessor[(formal, ...)] [: condition] -> successor [: probability]`;
// `-->`, `→`, `−` and `∧` are accepted for `->`, `-`, `-` and `^`. A condition `*` means none.
// Expressions: numbers, formals, defines, + - * / ^ (power), comparisons, && || !, and sqrt abs
// floor sin cos (degrees) min max.
//
// Aspen grammar files (.grammar): `key = number` lines setting AspenGrammarParams by their field
// names (and `name`, `model = "aspen-grammar"`, `leaf_shape`), each checked against its range.
//
// Every mistake throws sylva::ParseError "file:line: message".

#include "geometry/trees/lsystem/aspen_grammar.h"
#include "geometry/trees/lsystem/lsystem.h"

#include <filesystem>
#include <string>

namespace sylva {

struct LSystemSpecies {
  std::string name;
  LSystem system;
};

struct AspenGrammarSpecies {
  std::string name;
  AspenGrammarParams params;
};

LSystemSpecies parse_lsystem(const std::string& text, const std::filesystem::path& file);
AspenGrammarSpecies parse_aspen_grammar(const std::string& text, const std::filesystem::path& file);

}  // namespace sylva

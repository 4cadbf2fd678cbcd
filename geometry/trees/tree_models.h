#pragma once
// The registry of tree models. Each model's parameter struct lives in its own folder under
// geometry/trees/ and provides
//   static constexpr std::string_view kType;   // the species file's `model = "..."`
//   static P create(const Params&, std::vector<std::string>& warnings);  // its own schema
// plus a free function `TreeModel make_tree(const P&, uint64_t seed, const TreeOptions&)`, pure.
// Adding a model = its files + one entry in `TreeModelParams` below (and, for a file format of its
// own, one line in scenes/species.cpp's format table).

#include "geometry/trees/fournier_grindal/fournier_grindal.h"
#include "geometry/trees/hart_baker/hart_baker.h"
#include "geometry/trees/lsystem/aspen_grammar.h"
#include "geometry/trees/lsystem/lsystem.h"
#include "geometry/trees/tree_model.h"
#include "geometry/trees/treemaker/treemaker.h"
#include "geometry/trees/weber_penn/weber_penn.h"

#include <concepts>
#include <cstdint>
#include <variant>

namespace sylva {

// The registered tree models.
using TreeModelParams = std::variant<WeberPennParams, LSystem, AspenGrammarParams, TreeMakerTemplate, HartBakerParams,
                                     FournierGrindalParams>;

// Generates the tree structure for a seed. Pure: the same inputs give a bit-identical model.
// Constrained so a registered model without its own make_tree is a compile error, not a call of
// this function with the parameters converted back to the variant.
template <typename Variant>
requires std::same_as<Variant, TreeModelParams> TreeModel make_tree(const Variant& params, uint64_t seed,
                                                                    const TreeOptions& options = {}) {
  return std::visit([&](const auto& p) { return make_tree(p, seed, options); }, params);
}

}  // namespace sylva

#pragma once
// TreeModel: the structure a tree generator produces, before meshing (docs/design.md §5). Plain data,
// structs of vectors with index handles. Tree space: metres, Z up, trunk base at the origin.

#include "core/math.h"
#include "geometry/leaf_shape.h"
#include "geometry/solids/half_space.h"

#include <cstdint>
#include <vector>

namespace sylva {

// Stems: the trunk, branches and their clones. A stem's cross-sections are the contiguous range
// [first_section, first_section + section_count) of TreeModel::sections, from its base to its tip.
struct TreeStems {
  std::vector<uint8_t> level;     // 0 = trunk, 1 = main branches, ...
  std::vector<int32_t> parent;    // stem this one grows from, -1 for the trunk
  std::vector<int32_t> clone_of;  // stem this clone split from, -1 when not a clone
  std::vector<uint32_t> first_section;
  std::vector<uint32_t> section_count;
  std::vector<float> length_m;       // full length (a clone has its twin's length)
  std::vector<float> base_radius_m;  // radius at the stem base before flare and lobes
  std::vector<float> offset_m;       // position of the base along the parent, from its base
  std::vector<uint8_t> lobes;        // Weber & Penn §4.4 lobes; only the trunk has them
  std::vector<float> lobe_depth;
  // Empty, or one flag per stem: 1 marks a dead branch (the aspen grammar, seed 002 Ch. 6), which
  // a renderer may shade darker.
  std::vector<uint8_t> dead;

  size_t size() const { return level.size(); }
  bool is_clone(size_t i) const { return clone_of[i] >= 0; }
  bool is_dead(size_t i) const { return !dead.empty() && dead[i] != 0; }
};

// Cross-sections. `frames[k].z` is the stem direction: the spawn direction at a stem's first
// section (for a clone, its twin's direction at the split point) and the direction of the segment
// ending at the section otherwise. `arc_m` is the distance along the stem from its base (a clone
// continues its twin's), for bark texture coordinates. `radius_m` includes taper and flare.
struct StemSections {
  std::vector<Vec3> positions;
  std::vector<Frame> frames;
  std::vector<float> radius_m;
  std::vector<float> arc_m;

  size_t size() const { return positions.size(); }
};

// Leaves. The blade starts at `positions` (the petiole end) and runs along frames.z for length_m;
// frames.x spans its width, frames.y is the normal of its upper (adaxial) side.
struct TreeLeaves {
  std::vector<Vec3> positions;
  std::vector<Frame> frames;
  std::vector<float> length_m;
  std::vector<float> width_m;
  std::vector<LeafShape> shapes;
  std::vector<int32_t> stem;  // the stem carrying the leaf
  // Material slot per leaf: 0 = foliage, 1.. = further element materials (TREE-MAKER flowers and
  // fruit, docs/treemaker.md). Empty means every leaf is slot 0, so generators without flowers
  // need not fill it; otherwise it has one entry per leaf.
  std::vector<uint8_t> material;

  uint8_t material_of(size_t i) const { return material.empty() ? 0 : material[i]; }

  size_t size() const { return positions.size(); }
};

// How a tree is evaluated, for every model: wind (Weber & Penn §4.7; speed and gust in the paper's
// units) at time time_s, the §4.5 quality factor (leaf count and size, radial mesh resolution),
// and for growth models the age.
struct TreeOptions {
  float time_s = 0;
  float wind_speed = 0;
  float wind_gust = 0;
  float quality = 1;
  int years = 0;  // growth models (Hart-Baker): age in years; 0 = the species' own `years`
};

struct TreeModel {
  TreeStems stems;
  StemSections sections;
  TreeLeaves leaves;
  // Solids rendered by direct intersection rather than meshed (Fournier–Grindal crowns and trunks,
  // geometry/trees/fournier_grindal/); HalfSpaceSolid::material_slot 0 = bark, 1 = foliage.
  std::vector<HalfSpaceSolid> solids;
};

}  // namespace sylva

#pragma once
// TREE-MAKER (Neighbors & Hodges, seed 003): trees grown as a particle system from a tree template
// (§II, §V Figure 6). The template is plain typed data; scenes/species/treemaker_file.h reads the
// paper's text format into it. Sylva's readings of the places the paper leaves open are
// docs/treemaker.md.
//
// Template units are the paper's (a dogwood trunk segment is 15–25 units); `unit_m` turns them into
// metres. Angles are degrees as in the template.

#include "core/math.h"
#include "core/params.h"
#include "geometry/trees/tree_model.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace sylva {

// "low to high": a uniformly distributed random variable (§II: "All ranges given in the tree
// template are uniformly distributed random variables").
struct TreeMakerRange {
  float lo = 0.0f;
  float hi = 0.0f;
};

// color { name= r,g,b }: only the ratios matter (§V); the shade comes from a brightness range.
struct TreeMakerColor {
  std::string name;
  Vec3 rgb{1.0f};
};

// One (p= angle= dir= factor=) triplet of a branching rule (§II, Figure 1). `angle_deg` is the
// angle between the branch and its parent limb; `dir_deg` turns the branch about the parent limb,
// 0 and 180 being horizontal on either side and 90 straight up; `factor` scales the new
// particle's growth vector and lateral growth from its parent's.
struct TreeMakerBranchChoice {
  float p = 1.0f;
  TreeMakerRange angle_deg;
  TreeMakerRange dir_deg;
  TreeMakerRange factor;
};

// branch { level= n number= low to high (triplet)... }: governs branches of `level` and deeper up
// to the next rule (§IV: "the nearest level less than the current level"). Level 1 branches grow
// off the trunk. The number of branches per particle per iteration is the range's draw truncated.
struct TreeMakerBranchRule {
  int level = 1;
  TreeMakerRange number;
  std::vector<TreeMakerBranchChoice> choices;  // probabilities sum to 1
};

// particle { pos= mag= dir= acc= growth= age= color= brightness= }: a starting particle.
struct TreeMakerParticle {
  Vec3 pos{0.0f};              // template units
  TreeMakerRange mag;          // growth vector length, drawn every iteration (template units)
  Vec3 dir{0.0f, 0.0f, 1.0f};  // initial growth direction (need not be unit)
  float max_dev_deg = 0.0f;    // the ":maxdev_angle" of dir=
  float acc = 0.0f;            // added to both limits of `mag` after every iteration
  float growth = 0.0f;         // width added to each limb position per iteration
  float age = 0.0f;            // added to a limb position's growth per iteration
  int color = 0;               // index into TreeMakerTemplate::colors
  TreeMakerRange brightness{1.0f, 1.0f};
};

enum class TreeMakerCoord : uint8_t {
  Limb,  // z (out) along the branch, y (up) the world's up made perpendicular to it
  Leaf,  // y (up) the world's up, z (out) the branch direction made horizontal
};

// A tri= (3 points) or ln= (2 points) element of a leaf definition, in the leaf's coordinate
// system (template units), with the colour and brightness in force where it was written.
struct TreeMakerElement {
  std::vector<Vec3> points;
  int color = 0;
  TreeMakerRange brightness{1.0f, 1.0f};
  bool is_line() const { return points.size() == 2; }
};

// leaf { p= coord= out= up= color= brightness= tri=... ln=... }: a leaf, flower or fruit.
struct TreeMakerLeaf {
  float p = 1.0f;
  TreeMakerCoord coord = TreeMakerCoord::Limb;
  float out_deg = 0.0f;  // allowed deviation of the out (z) axis
  float up_deg = 0.0f;   // allowed deviation of the up (y) axis
  std::vector<TreeMakerElement> elements;
};

// light { ambient= lambert= height= radius= angle= }: the paper's shading weights (§III). Kept so
// a template round-trips; Sylva's path tracer does not use them (docs/treemaker.md).
struct TreeMakerLight {
  float ambient = 0.0f, lambert = 0.0f, height = 0.0f, radius = 0.0f, angle = 0.0f;
};

struct TreeMakerTemplate {
  int iterations = 1;
  float gravity = 0.0f;
  TreeMakerLight light;
  std::vector<TreeMakerColor> colors;
  std::vector<TreeMakerBranchRule> branches;  // ascending, distinct levels
  std::vector<TreeMakerParticle> particles;
  std::vector<TreeMakerLeaf> leaves;  // probabilities sum to 1
  // Sylva settings, not part of the paper's format.
  float unit_m = 0.03f;      // metres per template unit
  float line_width = 0.25f;  // width of the ribbon an ln= element becomes, template units
  // The .tmpl file a TOML species names (`template = ...`); scenes/species.cpp reads it.
  std::filesystem::path source;

  // Tree-model registry entry (geometry/trees/tree_models.h). A `.tmpl` file is read whole by
  // scenes/species/treemaker_file.h; a TOML species `model = "treemaker"` names one and may set
  // the Sylva settings: template = "dogwood.tmpl", unit_m = 0.03, line_width = 0.25. `create`
  // reads those keys (the template itself is parsed in scenes/, which owns the file format).
  static constexpr std::string_view kType = "treemaker";
  static TreeMakerTemplate create(const Params& params, std::vector<std::string>& warnings);

  // The rule for branches of `level` (≥ 1), or nullptr when no rule is at or below it.
  const TreeMakerBranchRule* rule_for_level(int level) const;
};

// The colour of each material the tree uses: bark from the particles, one element slot per
// distinct leaf-element colour in order of first use (TreeLeaves::material indexes them; in the
// dogwood slot 0 is the green of the leaves, slot 1 the white of the flowers). Each is the
// colour's normalised RGB (largest component 1) times the mean brightness over the elements (or
// particles) using it, linear and in [0, 1]; core/rgb_spectrum.h turns it into a reflectance.
struct TreeMakerMaterials {
  Vec3 bark_rgb{0.0f};
  std::vector<Vec3> element_rgb;
  std::vector<std::string> element_color_names;
};
TreeMakerMaterials treemaker_materials(const TreeMakerTemplate& tmpl);

// Grows one tree (§II) and puts a leaf definition at the end of every branch. Pure: the same
// template and seed give a bit-identical model. Every particle is one stem (level 0 for the
// starting particles, parent + 1 for branches) whose sections are its stored positions, radius
// half the stored width; every tri= element becomes one or two RightTriangle leaf quads and every
// ln= element a narrow Rectangle quad, on the particle's stem, in the material slot of its colour.
// Throws sylva::Error "tree too large: ..." when the growth exceeds the particle, section or leaf
// budget, and for a template whose colour indices or element point counts are invalid.
TreeModel make_treemaker_tree(const TreeMakerTemplate& tmpl, uint64_t seed);

// The registry's entry point: TREE-MAKER has no wind or level of detail, so `options` (Weber &
// Penn's sway and quality) do not change the model; the mesher still uses options.quality.
TreeModel make_tree(const TreeMakerTemplate& tmpl, uint64_t seed, const TreeOptions& options);

}  // namespace sylva

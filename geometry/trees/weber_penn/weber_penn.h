#pragma once
// The Weber & Penn (1995) tree generator: every parameter of the paper's appendix, plus the
// Arbaro extensions that have a clear meaning. Sylva's readings of the paper's ambiguous places
// are docs/design.md §5.1; the closed-form formulas live in geometry/trees/weber_penn/weber_penn_shape.h.

#include "core/params.h"
#include "geometry/leaf_shape.h"
#include "geometry/trees/tree_model.h"
#include "geometry/trees/weber_penn/weber_penn_shape.h"

#include <array>
#include <cmath>
#include <cstdint>

namespace sylva {

// Per-level parameters (the paper's nLength, nTaper, ...). Defaults are Arbaro's for level 1–3;
// WeberPennParams sets the level-0 defaults. Levels deeper than 3 reuse level 3.
struct WeberPennLevel {
  float length = 0.5f, length_v = 0.0f;                   // nLength, nLengthV
  float taper = 1.0f;                                     // nTaper in [0, 3)
  float seg_splits = 0.0f;                                // nSegSplits
  float split_angle = 0.0f, split_angle_v = 0.0f;         // degrees
  int curve_res = 3;                                      // nCurveRes
  float curve = 0.0f, curve_back = 0.0f, curve_v = 0.0f;  // degrees; curve_v < 0: helix
  float down_angle = 30.0f, down_angle_v = 0.0f;          // degrees; down_angle_v < 0: by position
  float rotate = 120.0f, rotate_v = 0.0f;                 // degrees; rotate < 0: alternating
  int branches = 5;                                       // nBranches; < 0: fan at the stem end
  float branch_dist = 1.0f;                               // Arbaro nBranchDist: 1 spread over a segment, 0 at its base
};

// Wind sway (§4.7); see wp::sway_angles. time_scale multiplies the phase rate (default 180/π as in
// Blender's Sapling; 1 is the literal reading, a trunk period of about 1.7 hours).
struct WeberPennWind {
  float speed = 0.0f;
  float gust = 0.0f;
  float time_s = 0.0f;
  float time_scale = 180.0f / kPi;
  bool active() const { return speed != 0.0f || gust != 0.0f; }
};

struct WeberPennParams {
  // The species-file model name (`model = "weber-penn"`); Arbaro XML files are read as this model.
  static constexpr std::string_view kType = "weber-penn";
  // Reads the paper's parameter names (weber_penn_params.cpp: names, ranges; defaults are the
  // member initialisers below, Arbaro's). Throws ParseError; parameters read but ignored (Arbaro's
  // Smooth, non-flat leaf shapes) add "file:line: warning: ..." to `warnings`.
  static WeberPennParams create(const Params& params, std::vector<std::string>& warnings);

  int shape = 0;                           // Shape 0..8 (ShapeRatio)
  float base_size = 0.25f;                 // BaseSize
  float scale = 10.0f, scale_v = 0.0f;     // Scale, ScaleV (metres)
  float z_scale = 1.0f, z_scale_v = 0.0f;  // ZScale, ZScaleV: vertical scaling of the whole tree
  int levels = 3;                          // Levels (stem levels, trunk = level 0)
  float ratio = 0.05f, ratio_power = 1.0f;
  int lobes = 0;
  float lobe_depth = 0.0f;
  float flare = 0.5f;
  float trunk_scale = 1.0f, trunk_scale_v = 0.0f;  // 0Scale, 0ScaleV
  int base_splits = 0;                             // 0BaseSplits
  std::array<WeberPennLevel, 4> level = [] {
    std::array<WeberPennLevel, 4> l{};
    l[0].length = 1.0f;
    l[0].down_angle = 0.0f;
    l[0].rotate = 0.0f;
    l[0].branches = 1;
    l[0].branch_dist = 0.0f;
    l[1].length = 0.5f;
    l[1].branches = 10;
    l[2].curve_res = 1;
    l[3].curve_res = 1;
    return l;
  }();
  int leaves = 0;  // Leaves; < 0: fan of |Leaves| at the stem end
  LeafShape leaf_shape = LeafShape::Oval;
  float leaf_scale = 0.2f, leaf_scale_x = 0.5f;
  float attraction_up = 0.0f;
  float prune_ratio = 0.0f;
  wp::Envelope envelope;  // PruneWidth, PruneWidthPeak, PrunePowerLow, PrunePowerHigh
  // Arbaro extensions.
  float leaf_bend = 0.3f;      // LeafBend: the 'bend' of §4.9
  float leaf_stem_len = 0.5f;  // LeafStemLen: petiole length as a fraction of the leaf length
  int leaf_distrib = 4;        // LeafDistrib: the shape of §4.5's leaf density (4 in the paper)
  float leaf_quality = 1.0f;   // LeafQuality: multiplies `quality` for the leaves
  // Which reading of the paper's ambiguous places (docs/weber_penn.md, "Readings"): the species
  // key `reading = "paper" | "arbaro"`; Arbaro XML files default to Arbaro's.
  wp::Reading reading = wp::Reading::Paper;
  // Evaluation settings (not species properties).
  float quality = 1.0f;  // §4.5 quality factor: leaf count ×quality, leaf size /√quality
  WeberPennWind wind;

  const WeberPennLevel& at(int stem_level) const { return level[static_cast<size_t>(std::min(stem_level, 3))]; }
  // Whether the parameters ask for stems below the ground: a trunk that may start below the
  // horizontal (|0DownAngle| + 0DownAngleV > 90°). Otherwise no geometry goes below z = 0.
  bool asks_below_ground() const { return std::abs(level[0].down_angle) + std::abs(level[0].down_angle_v) > 90.0f; }
};

// Generates one tree. Pure: the same params and seed give a bit-identical model; with wind the
// structure (stem and leaf counts, lengths) is that of the windless tree, only the curvature moves.
TreeModel make_weber_penn_tree(const WeberPennParams& params, uint64_t seed);
// The same with the evaluation options (wind at a time, quality) applied: the tree-model interface.
TreeModel make_tree(const WeberPennParams& params, uint64_t seed, const TreeOptions& options);

// Every parameter name a species file may use (with level prefixes 0..3), for documentation.
std::vector<std::string> weber_penn_parameter_names();

}  // namespace sylva

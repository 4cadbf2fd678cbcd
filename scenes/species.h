#pragma once
// Species files: a tree model and its parameters, read from Sylva TOML or Arbaro XML.
//
// Sylva TOML (Weber & Penn, seed 000; parameter names are the paper's, see docs/weber_penn.md):
//
//   model = "weber-penn"          # required
//   name = "Quaking Aspen"        # optional, defaults to the file name
//   Shape = 7                     # global parameters: Shape, BaseSize, Scale, ScaleV, ZScale, ZScaleV,
//   BaseSize = 0.4                #   Levels, Ratio, RatioPower, Lobes, LobeDepth, Flare, 0Scale,
//   ...                           #   0ScaleV, 0BaseSplits, Leaves, LeafShape, LeafScale, LeafScaleX,
//                                 #   AttractionUp, PruneRatio, PruneWidth, PruneWidthPeak,
//                                 #   PrunePowerLow, PrunePowerHigh, and Arbaro's LeafBend,
//                                 #   LeafStemLen, LeafDistrib, LeafQuality, Smooth (ignored)
//   [level1]                      # per level 0..3: Length, LengthV, Taper, SegSplits, SplitAngle,
//   DownAngle = 60                #   SplitAngleV, CurveRes, Curve, CurveBack, CurveV, DownAngle,
//   DownAngleV = -50              #   DownAngleV, Rotate, RotateV, Branches, BranchDist
//
// A level parameter may also be written with the paper's prefix at top level (`1DownAngle = 60`).
// Missing parameters take Arbaro's defaults. LeafShape is the paper's id (0 oval, 1 triangle,
// 2 oak3, 3 maple3, 4 maple5, 5 leaflets3) or one of those names.
//
// Arbaro XML: <arbaro><species name="..."><param name="1DownAngle" value="60"/>...</species></arbaro>.
//
// Every mistake (syntax, unknown or repeated parameter, wrong type, value out of range) throws
// sylva::ParseError "file:line: message". Parameters read but not used become warnings.

#include "geometry/mesh.h"
#include "geometry/trees/tree_model.h"
#include "geometry/trees/weber_penn/weber_penn.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

namespace sylva {

// How a tree is evaluated: wind (Weber & Penn §4.7; speed and gust in the paper's units) at time
// time_s, and the §4.5 quality factor (leaf count and size, radial mesh resolution).
struct TreeOptions {
  float time_s = 0;
  float wind_speed = 0;
  float wind_gust = 0;
  float quality = 1;
};

// The parameters of one tree model; a variant so other generators can join (docs/design.md §7).
using SpeciesModel = std::variant<WeberPennParams>;

struct Species {
  std::string name;
  std::filesystem::path file;
  SpeciesModel model;
  std::vector<std::string> warnings;  // "file:line: warning: ..." for parameters read but ignored
};

// Reads a species file by extension (.toml or .xml). Throws ParseError.
Species load_species(const std::filesystem::path& file);

// Parses species text; `file` names it in error messages and chooses the format by extension.
Species parse_species(const std::string& text, const std::filesystem::path& file);

// Generates the tree structure of a species for a seed. Pure.
TreeModel make_species_model(const Species& species, uint64_t seed, const TreeOptions& options = {});

// Generates and meshes a tree of the species. Pure: the same inputs give a bit-identical mesh.
TreeMesh make_species_mesh(const Species& species, uint64_t seed, const TreeOptions& options = {});

}  // namespace sylva

#pragma once
// Level of detail at range: Weber & Penn §5 ("Degradation at range") read for a path tracer
// (docs/lod.md). A tree is kept as four items — stem levels 0, 1, 2 (deeper levels grouped with
// 2) and the leaves — each cut into masses of consecutive elements (16 stem segments, 4 leaves) in
// the order they were made. A calibrated range r2 gives, per item, how many elements of every mass
// are drawn as polygons (tubes, leaf quads) and as lines or points (round curves, leaf discs).
// Unlike the paper's real-time reinterpretation, a path tracer builds a few levels per variant
// once and instances them; an element is drawn at most once (polygon, else line/point, else
// skipped), and the kept leaves (and kept stem lines) are enlarged so that each item's one-sided
// leaf area (projected bark area) is preserved. Pure and deterministic.

#include "geometry/grass.h"
#include "geometry/leaf_discs.h"
#include "geometry/mesh.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/tree_model.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sylva {

// Weber & Penn §5: "a mass_size of 16 for all the stems and 4 for the leaves".
inline constexpr int kLodStemMassSize = 16;
inline constexpr int kLodLeafMassSize = 4;
// Stem items: levels 0, 1 and 2 (§5: "any stems beyond the third level are grouped with the third").
inline constexpr int kLodStemItems = 3;

// The fewest leaves per mass a built level keeps (as points): one in four. Table 2 goes down to
// half a leaf per mass (one in eight), but the ×2.83 enlargement that then preserves the leaf
// area makes the leaves overlap measurably more, so a distant canopy lets more light through
// (+1.4 % green radiance over a test forest, mean-bias z = 5.6); one in four (×2) does not
// (docs/lod.md). lod_numbers keeps the paper's schedule.
inline constexpr float kLodMinLeafPoints = 1.0f;

// number_{primitive,item} of §5: elements per mass drawn with each primitive, in [0, mass_size].
struct LodNumbers {
  std::array<float, kLodStemItems> polygons{};  // stem segments drawn as tubes, of 16
  std::array<float, kLodStemItems> lines{};     // stem segments drawn as lines, of 16
  float leaf_polygons = 0;                      // leaves drawn as quads, of 4
  float leaf_points = 0;                        // leaves drawn as points, of 4
};

// The numbers at calibrated range r2 (summer, quality 1: the conditions of Table 2). Level 0 is the
// printed equation; levels 1, 2 and the leaves are fitted to Table 2 (the paper's text lost them;
// docs/lod.md gives the fits and their residuals).
LodNumbers lod_numbers(float r2);

// The paper's drawing loop (§5): of `total` elements in masses of `mass_size`, mass m draws its
// first floor(number) elements, plus one more in change = round(masses·frac(number)) of the
// masses — spread evenly (mass m when ⌊(m + 1)·change/masses⌋ > ⌊m·change/masses⌋), where the
// paper takes the first `change`; a last, partial mass of s < mass_size elements draws
// round(number·s/mass_size) of them. How many elements of
// mass `mass` are drawn, and whether element `index` is.
int lod_mass_drawn(size_t mass, size_t total, float number, int mass_size);
bool lod_is_drawn(size_t index, size_t total, float number, int mass_size);
size_t lod_drawn_count(size_t total, float number, int mass_size);

// §5's calibrated range r2 = range·1000/height_image·FOV_y/60, generalised to the footprint of one
// pixel: r2 is the range at which the paper's reference camera (1000 rows over a 60° vertical
// field of view) sees a pixel of `pixel_footprint_m`. For a pinhole camera at distance d,
// footprint = d·2·tan(vfov/2)/height.
float lod_calibrated_range(float pixel_footprint_m);

// The precomputed levels: level k is built at r2 = kLodLevelR2[k] (Table 2's ranges from 240 m) and
// drawn for instances with kLodLevelR2[k] ≤ r2 < kLodLevelR2[k + 1]; level 0 is the full tree.
// Table 2's 60 and 120 m columns keep 93 % and 53 % of the leaves as polygons: as prototypes of
// their own they would cost nearly a full tree's memory each for little saving, so trees closer
// than r2 = 240 are drawn in full (docs/lod.md).
inline constexpr std::array<float, 4> kLodLevelR2 = {0.0f, 240.0f, 600.0f, 1200.0f};
// The level for an instance at calibrated range r2 (non-decreasing in r2; 0 for r2 < 240 or NaN).
int lod_level_for(float r2);

// Drawn elements of one level, per stem item (segments) and for the leaves.
struct LodCounts {
  std::array<size_t, kLodStemItems> segments{};       // all segments of the item
  std::array<size_t, kLodStemItems> tube_segments{};  // drawn as tubes
  std::array<size_t, kLodStemItems> line_segments{};  // drawn as lines (and not as tubes)
  size_t leaves = 0, leaf_quads = 0, leaf_discs = 0;
};

// One level of a tree, in the tree's frame. Tubes are meshed by make_tree_mesh from the runs of
// consecutive tube segments (so a level's tubes are closed like the full tree's); lines are round
// cubic Bézier curves (straight, one per segment, radius along it); leaf quads keep their shape
// and outline, enlarged about the petiole; leaf discs sit at the quad's centre with the leaf's
// normal and a radius giving the leaf's outline area. `*_slot` is each leaf element's material
// slot (TreeLeaves::material_of).
struct TreeLod {
  float r2 = 0;
  TreeMesh mesh;  // stems, dead_stems (tubes), leaves (kept quads)
  std::vector<uint8_t> quad_slot;
  CurveSet lines, dead_lines;  // CurveSet::round
  LeafDiscs discs;
  std::vector<uint8_t> disc_slot;
  float leaf_scale = 1;                                         // linear enlargement of the kept leaves (slot 0)
  std::array<float, kLodStemItems> line_radius_scale{1, 1, 1};  // widening of the kept lines
  LodCounts counts;
};

// The level at r2 of a tree: `mesh` holds the tree's leaf quads, one per model leaf in order (its
// tubes are not read: they are meshed again from `model` with `options`: radial resolution, dead
// stems split). Per leaf material slot the
// one-sided leaf area (quad area × outline coverage) of the level equals the full tree's; per stem
// item the projected bark area Σ ½(r_i + r_{i+1})·|segment| of the drawn segments equals the full
// item's whenever any of its segments is drawn.
TreeLod make_tree_lod(const TreeModel& model, const TreeMesh& mesh, const TreeMeshOptions& options, float r2);

// One-sided leaf area of leaf quads (quad area × outline coverage) and of discs (π r²), m².
double leaf_outline_area(const LeafQuads& quads);

}  // namespace sylva

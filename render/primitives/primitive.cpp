#include "render/primitives/primitive.h"

#include "render/primitives/curves.h"
#include "render/primitives/discs.h"
#include "render/primitives/leaf_quads.h"
#include "render/primitives/solids.h"
#include "render/primitives/triangles.h"

namespace sylva {

void validate_prototype(const Prototype& p) {
  validate_triangles(p);
  validate_leaf_quads(p);
  validate_solids(p);
  validate_curves(p);
  validate_discs(p);
}

Bounds3 prototype_bounds(const Prototype& p) {
  Bounds3 b = triangles_bounds(p);
  b = merged(b, leaf_quads_bounds(p));
  b = merged(b, solids_bounds(p));
  b = merged(b, curves_bounds(p));
  return merged(b, discs_bounds(p));
}

}  // namespace sylva

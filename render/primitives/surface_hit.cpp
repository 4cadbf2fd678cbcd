#include "render/primitives/surface_hit.h"

namespace sylva {

void finish_surface_hit(const Ray& ray, const Instance& inst, const ObjectSurfaceHit& h, HitContext& si) {
  using namespace simd;
  // normal_from_object(inst): the cofactors of the linear part, signed by its determinant.
  const Columns3 m = linear_part(inst.world_from_object);
  Columns3 nfo{cross(m.c1, m.c2), cross(m.c2, m.c0), cross(m.c0, m.c1)};
  if (dot(m.c0, nfo.c0) < 0) {
    const __m128 sign = splat(-0.0f);
    nfo = {_mm_xor_ps(nfo.c0, sign), _mm_xor_ps(nfo.c1, sign), _mm_xor_ps(nfo.c2, sign)};
  }
  si.p = store(transform_point(inst.world_from_object, h.p));
  const __m128 ng = transform(nfo, h.ng);
  const float lg = std::sqrt(dot(ng, ng));  // glm::length
  si.ng = lg > 0 ? store(_mm_div_ps(ng, splat(lg))) : -ray.direction;
  if (!h.shading_normals) {
    si.ns = si.ng;  // what the lines below give for ns = ng, without computing it twice
    return;
  }
  const __m128 ns = transform(nfo, h.ns);
  const float ls = std::sqrt(dot(ns, ns));
  si.ns = ls > 0 ? store(_mm_div_ps(ns, splat(ls))) : si.ng;
  if (glm::dot(si.ns, si.ng) < 0) si.ns = -si.ns;
}

}  // namespace sylva

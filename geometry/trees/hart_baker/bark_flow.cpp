// Hart–Baker bark flow (§5.3): a chain of particles advanced up the limbs and relinked at every
// node, one flow line per particle.

#include "geometry/trees/hart_baker/surface_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sylva {

namespace surface_detail {
namespace {

// Keeps a ring of particle angles between the chain's link lengths (§5.3: maximum 3× minimum):
// splits the widest gaps while a link is too long, merges the narrowest while one is too short.
void respace(std::vector<float>& angles, float circumference, float spacing) {
  std::sort(angles.begin(), angles.end());
  const float max_link = 1.5f * spacing, min_link = 0.5f * spacing;
  const size_t least = std::max<size_t>(3, static_cast<size_t>(std::ceil(circumference / max_link)));
  const size_t most = std::max<size_t>(least, static_cast<size_t>(std::floor(circumference / min_link)));
  if (angles.empty()) angles.push_back(0.0f);
  auto gap = [&](size_t i) {
    const float next = i + 1 < angles.size() ? angles[i + 1] : angles[0] + 2 * kPi;
    return next - angles[i];
  };
  while (angles.size() < least) {
    size_t widest = 0;
    for (size_t i = 1; i < angles.size(); ++i)
      if (gap(i) > gap(widest)) widest = i;
    angles.insert(angles.begin() + static_cast<ptrdiff_t>(widest) + 1, wrap(angles[widest] + gap(widest) / 2));
    std::sort(angles.begin(), angles.end());
  }
  while (angles.size() > most) {
    size_t narrowest = 0;
    for (size_t i = 1; i < angles.size(); ++i)
      if (gap(i) < gap(narrowest)) narrowest = i;
    angles.erase(angles.begin() + static_cast<ptrdiff_t>(narrowest));
  }
}

// The flow's state: per stem, the ring of particle angles at its base and the flow line each
// particle extends (−1: a new line), and the stem as a cone with its frame.
struct FlowRings {
  std::vector<std::vector<float>> angles;
  std::vector<std::vector<int32_t>> line_of;
  std::vector<Frame> frames;
  std::vector<BlendCone> cones;
};

// The stems' cones and frames, and a ring at the base of every stem without a parent (a root).
FlowRings root_rings(const TreeModel& model, float spacing) {
  const size_t count = model.stems.size();
  FlowRings fr{std::vector<std::vector<float>>(count), std::vector<std::vector<int32_t>>(count),
               std::vector<Frame>(count), std::vector<BlendCone>(count)};
  for (size_t s = 0; s < count; ++s) {
    fr.cones[s] = stem_cone(model, s).cone;
    const Vec3 axis = fr.cones[s].tip - fr.cones[s].base;
    fr.frames[s] = Frame::from_z(glm::length(axis) > 0 ? glm::normalize(axis) : Vec3(0, 0, 1));
  }
  for (size_t s = 0; s < count; ++s) {
    if (model.stems.parent[s] >= 0) continue;
    respace(fr.angles[s], 2 * kPi * fr.cones[s].base_radius_m, spacing);
    fr.line_of[s].clear();
    for (size_t k = 0; k < fr.angles[s].size(); ++k) fr.line_of[s].push_back(-1);
  }
  return fr;
}

// Advances stem s's ring up the limb, one step per spacing, each particle extending its flow line
// (a new one for a new particle); the grain runs straight along a cone.
void advance_ring(FlowRings& fr, size_t s, float spacing, BarkFlow& flow) {
  const BlendCone& c = fr.cones[s];
  const Frame& f = fr.frames[s];
  const float length = glm::length(c.tip - c.base);
  const int steps = std::max(1, static_cast<int>(std::ceil(length / spacing)));
  for (size_t k = 0; k < fr.angles[s].size(); ++k) {
    int32_t line = fr.line_of[s][k];
    if (line < 0) {
      line = static_cast<int32_t>(flow.lines.size());
      flow.lines.emplace_back();
      flow.stems.emplace_back();
      fr.line_of[s][k] = line;
    }
    const float a = fr.angles[s][k];
    for (int i = 0; i <= steps; ++i) {
      const float t = static_cast<float>(i) / static_cast<float>(steps);
      const float r = (1 - t) * c.base_radius_m + t * c.tip_radius_m;
      flow.lines[static_cast<size_t>(line)].push_back(axis_point(c, t) + r * (std::cos(a) * f.x + std::sin(a) * f.y));
      flow.stems[static_cast<size_t>(line)].push_back(static_cast<int32_t>(s));
    }
  }
}

// The arcs of a stem's tip ring its children take: each lateral the arc centred on its direction,
// its half-width in proportion to its share of the children's radii; the continuation the rest.
struct ChildArcs {
  std::vector<float> centre, half_arc;
  int32_t continuation = -1;  // the continuation's index among the children
};

// The arcs of stem s's ring its children `kids` take.
ChildArcs child_arcs(const TreeModel& model, const std::vector<int32_t>& kids, const FlowRings& fr, size_t s) {
  float circumference_sum = 0;
  for (const int32_t ch : kids) circumference_sum += fr.cones[static_cast<size_t>(ch)].base_radius_m;
  ChildArcs arcs{std::vector<float>(kids.size()), std::vector<float>(kids.size()), -1};
  for (size_t j = 0; j < kids.size(); ++j) {
    const size_t ch = static_cast<size_t>(kids[j]);
    if (!is_lateral(model, ch)) {
      arcs.continuation = static_cast<int32_t>(j);
      continue;
    }
    arcs.centre[j] = angle_in(fr.frames[s], fr.frames[ch].z);
    arcs.half_arc[j] = kPi * fr.cones[ch].base_radius_m / circumference_sum;
  }
  return arcs;
}

// The child whose arc holds angle a (−1: none, the particle has reached the tip).
int32_t child_at(const ChildArcs& arcs, size_t children, float a) {
  int32_t to = arcs.continuation;
  float best = std::numeric_limits<float>::infinity();
  for (size_t j = 0; j < children; ++j) {
    if (static_cast<int32_t>(j) == arcs.continuation) continue;
    const float diff = std::abs(std::remainder(a - arcs.centre[j], 2 * kPi));
    if (diff < arcs.half_arc[j] && diff < best) {
      best = diff;
      to = static_cast<int32_t>(j);
    }
  }
  return to;
}

// The new ring of child j from the particles it took (angles and lines): relinking may add or
// drop particles; a kept particle continues its line, a new one starts its own.
void relink_child(FlowRings& fr, size_t ch, const std::vector<float>& taken, std::vector<int32_t>& taken_lines,
                  float spacing) {
  std::vector<float> ring = taken;
  respace(ring, 2 * kPi * fr.cones[ch].base_radius_m, spacing);
  std::vector<int32_t> lines(ring.size(), -1);
  for (size_t k = 0; k < ring.size(); ++k)
    for (size_t m = 0; m < taken.size(); ++m)
      if (taken[m] == ring[k] && taken_lines[m] >= 0) {
        lines[k] = taken_lines[m];
        taken_lines[m] = -1;
        break;
      }
  fr.angles[ch] = std::move(ring);
  fr.line_of[ch] = std::move(lines);
}

// Divides stem s's ring among its children (the relinking of Table 2).
void divide_ring(const TreeModel& model, const std::vector<int32_t>& kids, FlowRings& fr, size_t s, float spacing) {
  const Frame& f = fr.frames[s];
  const ChildArcs arcs = child_arcs(model, kids, fr, s);
  std::vector<std::vector<float>> child_angles(kids.size());
  std::vector<std::vector<int32_t>> child_lines(kids.size());
  for (size_t k = 0; k < fr.angles[s].size(); ++k) {
    const float a = fr.angles[s][k];
    const int32_t to = child_at(arcs, kids.size(), a);
    if (to < 0) continue;  // no continuation: the particle has reached the tip
    const size_t ch = static_cast<size_t>(kids[static_cast<size_t>(to)]);
    const Vec3 radial = std::cos(a) * f.x + std::sin(a) * f.y;
    float b;
    if (static_cast<int32_t>(to) == arcs.continuation) {
      b = angle_in(fr.frames[ch], radial);
    } else {
      // The arc closes into a loop around the lateral, its two ends meeting on the lateral's
      // side facing back down the parent.
      const float u =
          std::remainder(a - arcs.centre[static_cast<size_t>(to)], 2 * kPi) / arcs.half_arc[static_cast<size_t>(to)];
      b = angle_in(fr.frames[ch], -f.z) + kPi + kPi * u;
    }
    child_angles[static_cast<size_t>(to)].push_back(wrap(b));
    child_lines[static_cast<size_t>(to)].push_back(fr.line_of[s][k]);
  }
  for (size_t j = 0; j < kids.size(); ++j)
    relink_child(fr, static_cast<size_t>(kids[j]), child_angles[j], child_lines[j], spacing);
}

}  // namespace
}  // namespace surface_detail

BarkFlow hart_baker_bark_flow(const TreeModel& model, const HartBakerParams& params) {
  using namespace surface_detail;  // the internals (surface_detail.h)
  // §5.3's chain of particles, advanced along each limb and split at every node. A particle keeps
  // its angle about the limb (its momentum carries it straight up the grain); at a node the ring of particles divides
  // as Table 2's relinking divides the chain: each lateral takes the arc of the ring facing it, in proportion to its
  // share of the node's circumferences, closed into a loop around the lateral; the continuation takes the rest. The
  // springs' minimum and maximum link lengths become respace().
  const HartBakerBark& bark = params.bark;
  BarkFlow flow;
  if (model.stems.size() == 0) return flow;
  const std::vector<std::vector<int32_t>> children = stem_children(model);
  FlowRings fr = root_rings(model, bark.spacing_m);
  for (size_t s = 0; s < model.stems.size(); ++s) {
    advance_ring(fr, s, bark.spacing_m, flow);
    divide_ring(model, children[s], fr, s, bark.spacing_m);
  }
  return flow;
}

}  // namespace sylva

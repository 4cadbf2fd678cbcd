#pragma once
// The four species of Weber & Penn's appendix as WeberPennParams, for geometry tests that must not
// depend on the species-file parser (scenes/). Values as the appendix prints them.

#include "geometry/trees/weber_penn/weber_penn.h"

namespace sylva::test {

struct LevelRow {
  float length, length_v, taper, seg_splits, split_angle, split_angle_v;
  int curve_res;
  float curve, curve_back, curve_v, down_angle, down_angle_v, rotate, rotate_v;
  int branches;
};

inline void set_level(WeberPennParams& p, int n, const LevelRow& r) {
  WeberPennLevel& l = p.level[static_cast<size_t>(n)];
  l.length = r.length;
  l.length_v = r.length_v;
  l.taper = r.taper;
  l.seg_splits = r.seg_splits;
  l.split_angle = r.split_angle;
  l.split_angle_v = r.split_angle_v;
  l.curve_res = r.curve_res;
  l.curve = r.curve;
  l.curve_back = r.curve_back;
  l.curve_v = r.curve_v;
  l.down_angle = r.down_angle;
  l.down_angle_v = r.down_angle_v;
  l.rotate = r.rotate;
  l.rotate_v = r.rotate_v;
  l.branches = r.branches;
}

inline WeberPennParams quaking_aspen() {
  WeberPennParams p;
  p.shape = 7;
  p.base_size = 0.4f;
  p.scale = 13;
  p.scale_v = 3;
  p.z_scale = 1;
  p.z_scale_v = 0;
  p.levels = 3;
  p.ratio = 0.015f;
  p.ratio_power = 1.2f;
  p.lobes = 5;
  p.lobe_depth = 0.07f;
  p.flare = 0.6f;
  p.trunk_scale = 1;
  p.trunk_scale_v = 0;
  p.base_splits = 0;
  set_level(p, 0, {1, 0, 1, 0, 0, 0, 3, 0, 0, 20, 0, 0, 0, 0, 1});
  set_level(p, 1, {0.3f, 0, 1, 0, 0, 0, 5, -40, 0, 50, 60, -50, 140, 0, 50});
  set_level(p, 2, {0.6f, 0, 1, 0, 0, 0, 3, -40, 0, 75, 45, 10, 140, 0, 30});
  set_level(p, 3, {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 45, 10, 77, 0, 10});
  p.leaves = 25;
  p.leaf_shape = LeafShape::Oval;
  p.leaf_scale = 0.17f;
  p.leaf_scale_x = 1;
  p.attraction_up = 0.5f;
  p.prune_ratio = 0;
  p.envelope = {0.5f, 0.5f, 0.5f, 0.5f};
  return p;
}

inline WeberPennParams weeping_willow() {
  WeberPennParams p;
  p.shape = 3;
  p.base_size = 0.05f;
  p.scale = 15;
  p.scale_v = 5;
  p.z_scale = 1;
  p.z_scale_v = 0;
  p.levels = 4;
  p.ratio = 0.03f;
  p.ratio_power = 2;
  p.lobes = 9;
  p.lobe_depth = 0.03f;
  p.flare = 0.75f;
  p.trunk_scale = 1;
  p.trunk_scale_v = 0;
  p.base_splits = 2;
  set_level(p, 0, {0.8f, 0, 1, 0.1f, 3, 0, 8, 0, 20, 120, 0, 0, 0, 0, 1});
  set_level(p, 1, {0.5f, 0.1f, 1, 0.2f, 30, 10, 16, 40, 80, 90, 20, 10, -120, 30, 25});
  set_level(p, 2, {1.5f, 0, 1, 0.2f, 45, 20, 12, 0, 0, 0, 30, 10, -120, 30, 10});
  set_level(p, 3, {0.1f, 0, 1, 0, 0, 0, 1, 0, 0, 0, 20, 10, 140, 0, 300});
  p.leaves = 15;
  p.leaf_shape = LeafShape::Oval;
  p.leaf_scale = 0.12f;
  p.leaf_scale_x = 0.2f;
  p.attraction_up = -3;
  p.prune_ratio = 1;
  p.envelope = {0.4f, 0.6f, 0.001f, 0.5f};
  return p;
}

}  // namespace sylva::test

namespace sylva::test {

inline WeberPennParams black_tupelo() {
  WeberPennParams p;
  p.shape = 4;
  p.base_size = 0.2f;
  p.scale = 23;
  p.scale_v = 5;
  p.z_scale = 1;
  p.z_scale_v = 0;
  p.levels = 4;
  p.ratio = 0.015f;
  p.ratio_power = 1.3f;
  p.lobes = 3;
  p.lobe_depth = 0.1f;
  p.flare = 1;
  p.trunk_scale = 1;
  p.trunk_scale_v = 0;
  p.base_splits = 0;
  set_level(p, 0, {1, 0, 1.1f, 0, 0, 0, 10, 0, 0, 40, 0, 0, 0, 0, 1});
  set_level(p, 1, {0.3f, 0.05f, 1, 0, 0, 0, 10, 0, 0, 90, 60, -40, 140, 0, 50});
  set_level(p, 2, {0.6f, 0.1f, 1, 0, 0, 0, 10, -10, 0, 150, 30, 10, 140, 0, 25});
  set_level(p, 3, {0.4f, 0, 1, 0, 0, 0, 1, 0, 0, 0, 45, 10, 140, 0, 12});
  p.leaves = 6;
  p.leaf_shape = LeafShape::Oval;
  p.leaf_scale = 0.3f;
  p.leaf_scale_x = 0.5f;
  p.attraction_up = 0.5f;
  p.prune_ratio = 0;
  p.envelope = {0.5f, 0.5f, 0.5f, 0.5f};
  return p;
}

inline WeberPennParams california_black_oak() {
  WeberPennParams p;
  p.shape = 2;
  p.base_size = 0.05f;
  p.scale = 10;
  p.scale_v = 10;
  p.z_scale = 1;
  p.z_scale_v = 0;
  p.levels = 3;
  p.ratio = 0.018f;
  p.ratio_power = 1.3f;
  p.lobes = 5;
  p.lobe_depth = 0.1f;
  p.flare = 1.2f;
  p.trunk_scale = 1;
  p.trunk_scale_v = 0;
  p.base_splits = 2;
  set_level(p, 0, {1, 0, 0.95f, 0.4f, 10, 0, 8, 0, 0, 90, 0, 0, 0, 0, 1});
  set_level(p, 1, {0.8f, 0.1f, 1, 0.2f, 10, 10, 10, 40, -70, 150, 30, -30, 80, 0, 40});
  set_level(p, 2, {0.2f, 0.05f, 1, 0.1f, 10, 10, 3, 0, 0, -30, 45, 10, 140, 0, 120});
  set_level(p, 3, {0.4f, 0, 1, 0, 0, 0, 1, 0, 0, 0, 45, 10, 140, 0, 0});
  p.leaves = 25;
  p.leaf_shape = LeafShape::Oval;
  p.leaf_scale = 0.12f;
  p.leaf_scale_x = 0.66f;
  p.attraction_up = 0.8f;
  p.prune_ratio = 0;
  p.envelope = {0.5f, 0.5f, 0.5f, 0.5f};
  return p;
}

}  // namespace sylva::test

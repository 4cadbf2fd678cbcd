// Tree statistics (geometry/trees/tree_stats.h): the JSON of `sylva tree --stats`.

#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/tree_stats.h"

#include <gtest/gtest.h>

#include <string>

namespace sylva {
namespace {

TEST(TreeStats, EmptyTreeWritesValidJson) {
  // An empty tree (e.g. a trunk shorter than the smallest stem) has no bounds: null, not inf.
  const TreeModel model;
  const TreeMesh mesh = make_tree_mesh(model, {});
  const std::string json = tree_stats_json(compute_tree_stats(model, mesh), "empty", 1);
  EXPECT_EQ(json.find("inf"), std::string::npos) << json;
  EXPECT_EQ(json.find("nan"), std::string::npos) << json;
  EXPECT_NE(json.find("\"bbox_min\": null,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"bbox_max\": null,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"height_m\": 0.000000,"), std::string::npos) << json;
}

TEST(TreeStats, TreeWithGeometryWritesItsBounds) {
  TreeModel model;
  model.leaves.positions.push_back(Vec3(1.0f, 2.0f, 3.0f));
  model.leaves.frames.push_back(Frame{});
  model.leaves.length_m.push_back(0.5f);
  model.leaves.width_m.push_back(0.25f);
  model.leaves.shapes.push_back(LeafShape::Oval);
  model.leaves.stem.push_back(-1);
  const TreeMesh mesh = make_tree_mesh(model, {});
  const std::string json = tree_stats_json(compute_tree_stats(model, mesh), "one leaf", 1);
  EXPECT_NE(json.find("\"bbox_min\": [0.875000, 2.000000, 3.000000],"), std::string::npos) << json;
  EXPECT_NE(json.find("\"bbox_max\": [1.125000, 2.000000, 3.500000],"), std::string::npos) << json;
}

}  // namespace
}  // namespace sylva

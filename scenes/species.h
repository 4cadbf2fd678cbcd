#pragma once
// Species files: a tree model and its parameters. The format is chosen by the file's extension
// (a table in species.cpp: `.toml` Sylva TOML, `.xml` Arbaro XML, `.tmpl` a TREE-MAKER template,
// docs/treemaker.md); a TOML file names its model with
// `model = "..."`, dispatched through the tree-model registry (geometry/trees/tree_models.h), and
// the model reads its own parameters.
//
// Sylva TOML (the model's own parameter names; Weber & Penn's are documented in docs/weber_penn.md):
//
//   model = "weber-penn"          # required: a registered tree model
//   name = "Quaking Aspen"        # optional, defaults to the file name
//   Shape = 7                     # the model's parameters
//   [level1]                      # (Weber-Penn: per-level tables, or the paper's `1DownAngle`)
//   DownAngle = 60
//
// Arbaro XML: <arbaro><species name="..."><param name="1DownAngle" value="60"/>...</species></arbaro>,
// read as a Weber-Penn species.
//
// TREE-MAKER: a `.tmpl` file, or a TOML file `model = "treemaker"`, `template = "dogwood.tmpl"`
// (relative to the TOML file), optional `unit_m` (metres per template unit) and `line_width`.
//
// Hart-Baker (docs/hart_baker.md): a TOML file `model = "hart-baker"`, grown by make_species_model
// with the light-view pass, or a saved growth state `.hbtree` naming such a file, used as saved.
//
// Every mistake (syntax, unknown or repeated parameter, wrong type, value out of range) throws
// sylva::ParseError "file:line: message". Parameters read but not used become warnings.

#include "geometry/mesh.h"
#include "geometry/trees/tree_mesher.h"
#include "geometry/trees/tree_model.h"
#include "geometry/trees/tree_models.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

struct Species {
  std::string name;
  std::filesystem::path file;
  TreeModelParams model;
  std::vector<std::string> warnings;  // "file:line: warning: ..." for parameters read but ignored
};

// Reads a species file; the extension chooses the format. Throws ParseError.
Species load_species(const std::filesystem::path& file);

// Parses species text; `file` names it in error messages and chooses the format by extension.
Species parse_species(const std::string& text, const std::filesystem::path& file);

// The file extensions species files may have (".toml", ".xml", ...), for messages and docs.
std::vector<std::string> species_file_extensions();

// Generates the tree structure of a species for a seed. Pure.
TreeModel make_species_model(const Species& species, uint64_t seed, const TreeOptions& options = {});

// Meshes a model of the species: the shared mesher (geometry/trees/tree_mesher.h), except a
// Hart–Baker tree's blended joints and bark (geometry/trees/hart_baker/surface.h).
TreeMesh mesh_species_model(const Species& species, const TreeModel& model, const TreeMeshOptions& options);

// Generates and meshes a tree of the species. Pure: the same inputs give a bit-identical mesh.
TreeMesh make_species_mesh(const Species& species, uint64_t seed, const TreeOptions& options = {});

}  // namespace sylva

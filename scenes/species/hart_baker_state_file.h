#pragma once
// Saved Hart–Baker growth states (`sylva grow --save TREE.hbtree`): a text file that names its
// species file and holds every limb's Table 1 state and growth rings, so growth can continue
// (`sylva grow TREE.hbtree --years N`) and a scene can use the grown tree like a species
// ([[trees]] species = "TREE.hbtree"). Format (docs/hart_baker.md "State files"), one record a line:
//
//   sylva-hart-baker-state 1
//   species <path of the species file, relative to this file or absolute>
//   seed <n>
//   year <n>
//   limb <parent> <order> <alive> <born> <base x y z> <direction x y z> <length> <radius>
//        <apex> <lit> <reaction x y z>                             (one line; ids count from 0)
//   ring <radius> <length> <offset x y z>          (the last limb's rings by year; living limbs only)
//
// Reals are written with 9 significant digits, so a float state reads back bit for bit and
// continuing a saved tree gives the same tree as growing it in one go.

#include "geometry/trees/hart_baker/hart_baker.h"

#include <filesystem>
#include <string>

namespace sylva {

struct HartBakerStateFile {
  std::filesystem::path species;  // as written in the file, resolved against the file's directory
  HartBakerTree tree;
};

// Throws ParseError (file:line: ...) for any mistake.
HartBakerStateFile parse_hart_baker_state(const std::string& text, const std::filesystem::path& file);

// Reads a state file; `species` comes back resolved against the file's directory.
HartBakerStateFile load_hart_baker_state(const std::filesystem::path& file);

// The state's text; `species` is written as given.
std::string format_hart_baker_state(const HartBakerTree& tree, const std::filesystem::path& species);

}  // namespace sylva

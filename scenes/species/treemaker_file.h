#pragma once
// TREE-MAKER tree templates (.tmpl): the text format of Neighbors & Hodges, §V Figure 6, read into
// a TreeMakerTemplate (geometry/trees/treemaker/treemaker.h). docs/treemaker.md describes it.
//
//   iterations { i= 13 }
//   gravity    { g= 0.08 }
//   light      { ambient=0.1 lambert=0.4 height=0.4 radius=0.3 angle=0.2 }
//   color      { brown= 1,0.9,0.2 }
//   branch     { level= 1 number= 2.0 to 3.0
//                (p=1 angle= 40 to 80 dir= 0 to 360 factor= 0.5 to 0.7) }
//   particle   { pos=0,0,0 mag= 15 to 25 dir= 0,0,1:10 acc= -0.8
//                growth= 0.4 age= 0 color= brown brightness= 0.2 to 0.5 }
//   leaf       { p= 1 coord= leaf out= 30 up= 10 color= green brightness= 0.4 to 0.8
//                tri= 0,0,0 0,-9,3 -3,-3,4 ln= 0,0,0 0,-2,1 }
//
// As the figure's notes say: any spacing (line breaks included) as long as the braces,
// parentheses and equal signs are right; the branch rules come before the particles; the
// probabilities of each rule's triplets, and of the leaf definitions, add up to one; "low to high"
// is a range (a single number is the range from it to itself). Sylva's additions: `#` starts a
// comment to the end of the line, and a colour must be defined before it is used.
//
// Every mistake throws sylva::ParseError "file:line: message": unknown sections or keywords,
// missing or malformed values, values out of range, repeated keywords, sections or levels,
// undefined colours, probabilities not summing to 1, rules after particles, a missing iterations,
// branch, particle or leaf section. Never crashes or hangs on any input.

#include "geometry/trees/treemaker/treemaker.h"

#include <filesystem>
#include <string>

namespace sylva {

TreeMakerTemplate parse_treemaker_template(const std::string& text, const std::filesystem::path& file);

// Reads and parses a template file. Throws ParseError (line 0 when the file cannot be opened).
TreeMakerTemplate load_treemaker_template(const std::filesystem::path& file);

}  // namespace sylva

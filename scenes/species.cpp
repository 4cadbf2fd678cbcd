#include "scenes/species.h"

#include "core/data_path.h"
#include "core/error.h"
#include "core/input_file.h"
#include "core/registry.h"
#include "geometry/trees/hart_baker/surface.h"
#include "geometry/trees/tree_mesher.h"
#include "scenes/hart_baker_growth.h"
#include "scenes/species/hart_baker_state_file.h"
#include "scenes/species/lsystem_file.h"
#include "scenes/species/treemaker_file.h"
#include "scenes/toml_reader.h"

#include <fmt/core.h>
#include <toml++/toml.h>
#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

namespace sylva {

namespace {

bool parse_double(std::string_view s, double& out) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && ptr == s.data() + s.size();
}

Species parse_toml(const std::string& text, const std::filesystem::path& file) {
  TomlReader reader(file.string());
  const toml::table root = reader.parse(text);
  // Files a species names (a TREE-MAKER template) resolve against the species file's directory,
  // then Sylva's data directory.
  const FileResolver resolver = [dir = file.parent_path()](const std::string& rel) {
    return find_named_file(dir, rel);
  };
  const Params params = reader.to_params(root, "the species file", resolver);
  Species species;
  species.file = file;
  species.name = params.string("name", file.stem().string());
  if (!params.has("model")) reader.fail_line(1, "missing key 'model' (e.g. model = \"weber-penn\")");
  const std::string model = params.string("model");
  std::optional<TreeModelParams> created = create_registered<TreeModelParams>(model, params, species.warnings);
  if (!created)
    params.fail("model", fmt::format("unknown model \"{}\" (this version reads {})", model,
                                     registered_names<TreeModelParams>()));
  species.model = std::move(*created);
  // A TREE-MAKER species names its template file; the Figure 6 format is read here, in scenes/.
  if (TreeMakerTemplate* t = std::get_if<TreeMakerTemplate>(&species.model)) {
    TreeMakerTemplate loaded = load_treemaker_template(t->source);
    loaded.unit_m = t->unit_m;
    loaded.line_width = t->line_width;
    loaded.source = t->source;
    *t = std::move(loaded);
  }
  return species;
}

// A TREE-MAKER template (Neighbors & Hodges §V, Figure 6; docs/treemaker.md).
Species parse_treemaker(const std::string& text, const std::filesystem::path& file) {
  Species species;
  species.file = file;
  species.name = file.stem().string();
  TreeMakerTemplate t = parse_treemaker_template(text, file);
  t.source = file;
  species.model = std::move(t);
  return species;
}

int line_at(const std::string& text, ptrdiff_t offset) {
  if (offset < 0) return 0;
  const auto end = text.begin() + std::min<ptrdiff_t>(offset, static_cast<ptrdiff_t>(text.size()));
  return 1 + static_cast<int>(std::count(text.begin(), end, '\n'));
}

Species parse_arbaro_xml(const std::string& text, const std::filesystem::path& file) {
  pugi::xml_document doc;
  const pugi::xml_parse_result result = doc.load_buffer(text.data(), text.size());
  if (!result) throw ParseError(file, line_at(text, result.offset), fmt::format("XML: {}", result.description()));
  const pugi::xml_node root = doc.child("arbaro");
  if (!root) throw ParseError(file, 1, "not an Arbaro species file: expected an <arbaro> root element");
  const pugi::xml_node sp = root.child("species");
  if (!sp) throw ParseError(file, line_at(text, root.offset_debug()), "<arbaro> has no <species> element");

  Species species;
  species.file = file;
  species.name = sp.attribute("name") ? sp.attribute("name").value() : file.stem().string();
  Params params(file.string(), line_at(text, sp.offset_debug()), "<species>");
  for (const pugi::xml_node node : sp.children()) {
    if (node.type() != pugi::node_element) continue;
    const int line = line_at(text, node.offset_debug());
    if (std::string_view(node.name()) != "param")
      throw ParseError(file, line,
                       fmt::format("unexpected <{}> in <species> (expected <param name=... value=.../>)", node.name()));
    const pugi::xml_attribute name = node.attribute("name");
    const pugi::xml_attribute value = node.attribute("value");
    if (!name) throw ParseError(file, line, "<param> without a name attribute");
    if (!value)
      throw ParseError(file, line, fmt::format("<param name=\"{}\"> without a value attribute", name.value()));
    const std::string pname = name.value();
    if (pname == "Species") {
      species.name = value.value();
      continue;
    }
    ParamValue v;
    v.line = line;
    v.kind = parse_double(value.value(), v.real) ? ParamValue::Kind::Real : ParamValue::Kind::String;
    v.string = value.value();
    params.add(pname, std::move(v));
  }
  // An Arbaro library reads as Arbaro reads it unless the file says otherwise (docs/weber_penn.md).
  const bool has_reading = params.has("reading");
  WeberPennParams weber_penn = WeberPennParams::create(params, species.warnings);
  if (!has_reading) weber_penn.reading = wp::Reading::Arbaro;
  species.model = weber_penn;
  return species;
}

// The species file formats, by extension. Adding a format = one line here.
struct SpeciesFormat {
  std::string_view extension;
  Species (*parse)(const std::string& text, const std::filesystem::path& file);
};
Species parse_lsys(const std::string& text, const std::filesystem::path& file) {
  LSystemSpecies l = parse_lsystem(text, file);
  return Species{std::move(l.name), file, std::move(l.system), {}};
}

Species parse_grammar(const std::string& text, const std::filesystem::path& file) {
  AspenGrammarSpecies a = parse_aspen_grammar(text, file);
  return Species{std::move(a.name), file, a.params, {}};
}

// A saved Hart-Baker growth state (docs/hart_baker.md): the species it names, grown as saved.
Species parse_hart_baker_tree(const std::string& text, const std::filesystem::path& file) {
  HartBakerStateFile state = parse_hart_baker_state(text, file);
  const std::filesystem::path species_file =
      state.species.is_absolute() ? state.species : file.parent_path() / state.species;
  Species species = load_species(species_file);
  HartBakerParams* params = std::get_if<HartBakerParams>(&species.model);
  if (!params)
    throw ParseError(file, 2,
                     fmt::format("{} is not a Hart-Baker species (model = \"hart-baker\")", species_file.string()));
  params->grown = std::make_shared<const HartBakerTree>(std::move(state.tree));
  species.file = file;
  species.name = fmt::format("{} (year {})", species.name, params->grown->year);
  return species;
}

constexpr SpeciesFormat kSpeciesFormats[] = {
    {".toml", parse_toml},               // Sylva TOML, any registered model
    {".xml", parse_arbaro_xml},          // Arbaro XML (Weber-Penn)
    {".lsys", parse_lsys},               // L-systems (docs/lsystems.md)
    {".grammar", parse_grammar},         // the aspen grammar (docs/lsystems.md)
    {".tmpl", parse_treemaker},          // TREE-MAKER templates (docs/treemaker.md)
    {".hbtree", parse_hart_baker_tree},  // saved Hart-Baker growth states (docs/hart_baker.md)
};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace

std::vector<std::string> species_file_extensions() {
  std::vector<std::string> out;
  for (const SpeciesFormat& f : kSpeciesFormats) out.emplace_back(f.extension);
  return out;
}

Species parse_species(const std::string& text, const std::filesystem::path& file) {
  const std::string ext = lower(file.extension().string());
  for (const SpeciesFormat& f : kSpeciesFormats)
    if (ext == f.extension) return f.parse(text, file);
  std::string known;
  for (const SpeciesFormat& f : kSpeciesFormats) known += (known.empty() ? "" : " or ") + std::string(f.extension);
  throw ParseError(file, 0, fmt::format("unknown species file type (expected {})", known));
}

Species load_species(const std::filesystem::path& file) {
  return parse_species(read_input_file(file, kMaxSpeciesFileBytes, "species file"), file);
}

TreeModel make_species_model(const Species& species, uint64_t seed, const TreeOptions& options) {
  // A Hart-Baker species grows here, where the light-view pass is available (docs/design.md §2).
  if (const HartBakerParams* hb = std::get_if<HartBakerParams>(&species.model); hb && !hb->grown)
    return hart_baker_tree_model(grow_hart_baker_tree(*hb, seed, options.years > 0 ? options.years : hb->years, {}),
                                 *hb);
  return make_tree(species.model, seed, options);
}

TreeMesh make_species_mesh(const Species& species, uint64_t seed, const TreeOptions& options) {
  TreeMeshOptions mesh_options;
  mesh_options.quality = options.quality;
  // The aspen grammar's <linear_pt> is an 8-point circle (thesis Ch. 6).
  if (std::holds_alternative<AspenGrammarParams>(species.model)) mesh_options.radial_segments = {8, 8, 8, 8};
  return mesh_species_model(species, make_species_model(species, seed, options), mesh_options);
}

TreeMesh mesh_species_model(const Species& species, const TreeModel& model, const TreeMeshOptions& options) {
  if (const HartBakerParams* hb = std::get_if<HartBakerParams>(&species.model))
    return make_hart_baker_mesh(model, *hb, options);
  return make_tree_mesh(model, options);
}

}  // namespace sylva

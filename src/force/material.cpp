#include "deflex/force/material.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/profile/yaml.hpp"

namespace deflex::force {

namespace {

std::string fold(const std::string& s) {
  std::string out;
  for (char c : s)
    if (c != ' ' && c != '-' && c != '_') out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// The coefficients of the entry's model; keys of the other model are errors.
void read_coefficients(const yaml::Map& n, const std::string& model, MaterialEntry& m) {
  auto forbid = [&](std::initializer_list<const char*> keys) {
    for (const char* k : keys)
      if (n.has(k)) n.fail(k, std::string(k) + " does not belong to model " + model);
  };
  if (model == "mechanistic") {
    forbid({"K_T_N_per_mm2", "K_R_N_per_mm2", "K_A_N_per_mm2"});
    m.form = ModelForm::mechanistic;
    m.k.Ktc_N_per_mm2 = n.number("K_tc_N_per_mm2");
    m.k.Krc_N_per_mm2 = n.number("K_rc_N_per_mm2");
    m.k.Kac_N_per_mm2 = n.number("K_ac_N_per_mm2", 0, {});
    m.k.Kte_N_per_mm = n.number("K_te_N_per_mm", 0, {});
    m.k.Kre_N_per_mm = n.number("K_re_N_per_mm", 0, {});
    m.k.Kae_N_per_mm = n.number("K_ae_N_per_mm", 0, {});
  } else if (model == "smaoui_krta") {
    forbid({"K_tc_N_per_mm2", "K_rc_N_per_mm2", "K_ac_N_per_mm2", "K_te_N_per_mm", "K_re_N_per_mm", "K_ae_N_per_mm"});
    m.form = ModelForm::smaoui_krta;
    m.k = from_smaoui(n.number("K_T_N_per_mm2"), n.number("K_R_N_per_mm2"), n.number("K_A_N_per_mm2"));
  } else {
    n.fail("model", "unknown model '" + model + "' (expected mechanistic or smaoui_krta)");
  }
  if (m.k.Ktc_N_per_mm2 <= 0) n.fail(n.node(), "the tangential cutting coefficient must be > 0");
}

// `elastic: {E_MPa, poisson}`, the form of a tool library's material.
ElasticConstants read_elastic(const YAML::Node& node, const std::string& file) {
  if (!node.IsMap()) yaml::fail(file, node.Mark(), "elastic must be a map {E_MPa: .., poisson: ..}");
  const yaml::Map n(node, "elastic", file, {"E_MPa", "poisson"});
  ElasticConstants e;
  e.E_MPa = n.number("E_MPa", yaml::Range::positive());
  e.poisson = n.number("poisson");
  // Isotropic elasticity is positive definite only for -1 < nu < 0.5.
  if (!(e.poisson > -1.0 && e.poisson < 0.5)) n.fail("poisson", "poisson must be in (-1, 0.5)");
  return e;
}

MaterialEntry parse_entry(const YAML::Node& node, const std::string& name, const std::string& file) {
  const yaml::Map n(node, "material '" + name + "'", file,
                    {"aliases", "model", "source", "conditions", "notes", "K_tc_N_per_mm2", "K_rc_N_per_mm2",
                     "K_ac_N_per_mm2", "K_te_N_per_mm", "K_re_N_per_mm", "K_ae_N_per_mm", "K_T_N_per_mm2",
                     "K_R_N_per_mm2", "K_A_N_per_mm2", "elastic"});
  MaterialEntry m;
  m.name = name;
  m.location = yaml::where(file, node.Mark());
  if (n.has("aliases")) {
    const YAML::Node a = n.get("aliases");
    if (!a.IsSequence()) n.fail(a, "aliases must be a list of names");
    for (const auto& x : a) m.aliases.push_back(yaml::text(x, "an alias", file));
  }
  const std::string model = n.text("model");
  m.source = n.text("source");
  if (m.source.empty()) n.fail("source", "source must not be empty");
  m.conditions = n.text("conditions", "");
  m.notes = n.text("notes", "");
  if (n.has("elastic")) m.elastic = read_elastic(n.get("elastic"), file);
  read_coefficients(n, model, m);
  return m;
}

}  // namespace

MaterialLibrary parse_material_library(const std::string& yaml_text, const std::string& file) {
  const YAML::Node root = yaml::load_text(yaml_text, file);
  if (!root.IsMap() || !root["materials"])
    yaml::fail(file, root.Mark(), "expected a map with a 'materials:' key");
  const YAML::Node mats = yaml::Map(root, "material library", file, {"materials"}).get("materials");
  if (!mats.IsMap()) yaml::fail(file, mats.Mark(), "materials must be a map");
  MaterialLibrary lib;
  lib.file = file;
  for (const auto& kv : mats) {
    MaterialEntry m = parse_entry(kv.second, yaml::text(kv.first, "a material name", file), file);
    for (const auto& other : lib.entries) {
      std::vector<std::string> a = other.aliases, b = m.aliases;
      a.push_back(other.name);
      b.push_back(m.name);
      for (const auto& x : a)
        for (const auto& y : b)
          if (fold(x) == fold(y))
            yaml::fail(file, kv.first.Mark(), "name '" + y + "' is already used by material '" + other.name + "'");
    }
    lib.entries.push_back(std::move(m));
  }
  return lib;
}

MaterialLibrary load_material_library(const std::string& path) {
  return parse_material_library(yaml::read_file(path), path);
}

const MaterialEntry& find_material(const MaterialLibrary& lib, const std::string& name) {
  const std::string key = fold(name);
  for (const auto& m : lib.entries) {
    if (fold(m.name) == key) return m;
    for (const auto& a : m.aliases)
      if (fold(a) == key) return m;
  }
  std::string known;
  for (const auto& m : lib.entries) known += (known.empty() ? "" : ", ") + m.name;
  throw Error(ErrorKind::settings, "unknown material '" + name + "' in " + lib.file + " (known: " + known + ")");
}

std::string to_yaml(const MaterialEntry& m) {
  auto q = [](const std::string& s) {
    std::string out = "\"";
    for (char c : s) out += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    return out + "\"";
  };
  auto num = [](double v) {
    char b[64];
    std::snprintf(b, sizeof b, "%.6g", v);
    return std::string(b);
  };
  std::ostringstream o;
  o << "materials:\n  " << q(m.name) << ":\n";
  if (!m.aliases.empty()) {
    o << "    aliases: [";
    for (std::size_t i = 0; i < m.aliases.size(); ++i) o << (i ? ", " : "") << q(m.aliases[i]);
    o << "]\n";
  }
  o << "    model: " << to_string(m.form) << "\n";
  if (m.form == ModelForm::smaoui_krta) {
    o << "    K_T_N_per_mm2: " << num(m.k.Ktc_N_per_mm2) << "\n"
      << "    K_R_N_per_mm2: " << num(m.k.Krc_N_per_mm2) << "\n"
      << "    K_A_N_per_mm2: " << num(m.k.Kac_N_per_mm2) << "\n";
  } else {
    o << "    K_tc_N_per_mm2: " << num(m.k.Ktc_N_per_mm2) << "\n"
      << "    K_rc_N_per_mm2: " << num(m.k.Krc_N_per_mm2) << "\n"
      << "    K_ac_N_per_mm2: " << num(m.k.Kac_N_per_mm2) << "\n"
      << "    K_te_N_per_mm: " << num(m.k.Kte_N_per_mm) << "\n"
      << "    K_re_N_per_mm: " << num(m.k.Kre_N_per_mm) << "\n"
      << "    K_ae_N_per_mm: " << num(m.k.Kae_N_per_mm) << "\n";
  }
  o << "    source: " << q(m.source) << "\n";
  if (!m.conditions.empty()) o << "    conditions: " << q(m.conditions) << "\n";
  if (!m.notes.empty()) o << "    notes: " << q(m.notes) << "\n";
  if (m.elastic)
    o << "    elastic: {E_MPa: " << num(m.elastic->E_MPa) << ", poisson: " << num(m.elastic->poisson) << "}\n";
  return o.str();
}

}  // namespace deflex::force

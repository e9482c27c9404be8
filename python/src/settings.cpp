// The keyword names of job::Settings (settings.hpp here): one table, read by
// both directions, so a field added to the table is reachable both ways.
#include "settings.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace deflex::python {
namespace {

using job::Settings;

struct Field {
  const char* name;
  std::function<void(Settings&, py::handle)> set;
  std::function<py::object(const Settings&)> get;
};

[[noreturn]] void wrong_type(const char* name, const char* expected, py::handle v) {
  throw py::type_error(std::string(name) + ": expected " + expected + ", got " +
                       std::string(py::str(py::type::of(v).attr("__name__"))));
}

// A str or an os.PathLike (pathlib.Path): paths are the common case.
std::string text(const char* name, py::handle v) {
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::hasattr(v, "__fspath__")) return py::str(py::module_::import("os").attr("fspath")(v)).cast<std::string>();
  wrong_type(name, "a str or a path", v);
}

double number(const char* name, py::handle v) {
  // bool is an int in Python: refused, tolerance_mm=True is a mistake.
  if (py::isinstance<py::bool_>(v) ||
      !(py::isinstance<py::float_>(v) || py::isinstance<py::int_>(v) || py::hasattr(v, "__float__")))
    wrong_type(name, "a number", v);
  return py::cast<double>(v);
}

template <class Int>
Int integer(const char* name, py::handle v) {
  if (py::isinstance<py::bool_>(v) || !py::isinstance<py::int_>(v)) wrong_type(name, "an int", v);
  return v.cast<Int>();
}

bool flag(const char* name, py::handle v) {
  if (!py::isinstance<py::bool_>(v)) wrong_type(name, "a bool", v);
  return v.cast<bool>();
}

template <class Ref>
Field path_field(const char* name, Ref ref) {
  return {name, [=](Settings& s, py::handle v) { ref(s) = text(name, v); },
          [=](const Settings& s) { return py::object(py::str(ref(const_cast<Settings&>(s)))); }};
}

template <class Ref>
Field optional_field(const char* name, Ref ref) {
  return {name, [=](Settings& s, py::handle v) { ref(s) = number(name, v); },
          [=](const Settings& s) {
            const std::optional<double>& o = ref(const_cast<Settings&>(s));
            return o ? py::object(py::float_(*o)) : py::object(py::none());
          }};
}

template <class Ref>
Field number_field(const char* name, Ref ref) {
  return {name, [=](Settings& s, py::handle v) { ref(s) = number(name, v); },
          [=](const Settings& s) { return py::object(py::float_(ref(const_cast<Settings&>(s)))); }};
}

template <class Int, class Ref>
Field int_field(const char* name, Ref ref) {
  return {name, [=](Settings& s, py::handle v) { ref(s) = integer<Int>(name, v); },
          [=](const Settings& s) { return py::object(py::int_(ref(const_cast<Settings&>(s)))); }};
}

template <class Ref>
Field bool_field(const char* name, Ref ref) {
  return {name, [=](Settings& s, py::handle v) { ref(s) = flag(name, v); },
          [=](const Settings& s) { return py::object(py::bool_(ref(const_cast<Settings&>(s)))); }};
}

// stock_from: [path, (program, tool_file), ...], in the order the programs ran.
std::vector<job::EarlierOp> earlier_ops(py::handle v) {
  if (py::isinstance<py::str>(v) || !py::isinstance<py::sequence>(v))
    wrong_type("stock_from", "a list of paths or (program, tool_file) pairs", v);
  std::vector<job::EarlierOp> ops;
  for (py::handle e : v) {
    if (py::isinstance<py::tuple>(e) || py::isinstance<py::list>(e)) {
      const py::sequence pair = py::reinterpret_borrow<py::sequence>(e);
      if (pair.size() != 2) wrong_type("stock_from", "(program, tool_file) pairs", e);
      ops.push_back({text("stock_from", pair[0]), text("stock_from", pair[1])});
    } else {
      ops.push_back({text("stock_from", e), ""});
    }
  }
  return ops;
}

Field stock_from_field() {
  return {"stock_from", [](Settings& s, py::handle v) { s.stock_from = earlier_ops(v); },
          [](const Settings& s) {
            py::list l;
            for (const job::EarlierOp& e : s.stock_from)
              l.append(e.tool_file.empty() ? py::object(py::str(e.program))
                                           : py::object(py::make_tuple(e.program, e.tool_file)));
            return py::object(l);
          }};
}

// fixture: one "box:X0,Y0,Z0,X1,Y1,Z1" or a list of them.
Field fixture_field() {
  return {"fixture",
          [](Settings& s, py::handle v) {
            std::vector<std::string>& f = s.workholding.fixtures;
            f.clear();
            if (py::isinstance<py::str>(v)) {
              f.push_back(text("fixture", v));
              return;
            }
            if (!py::isinstance<py::sequence>(v)) wrong_type("fixture", "a box:X0,Y0,Z0,X1,Y1,Z1 or a list of them", v);
            for (py::handle e : v) f.push_back(text("fixture", e));
          },
          [](const Settings& s) {
            py::list l;
            for (const std::string& b : s.workholding.fixtures) l.append(b);
            return py::object(l);
          }};
}

// block_delete: True/False, or the command line's "on"/"off".
Field block_delete_field() {
  return {"block_delete",
          [](Settings& s, py::handle v) {
            s.read.block_delete =
                py::isinstance<py::bool_>(v) ? (v.cast<bool>() ? "on" : "off") : text("block_delete", v);
          },
          [](const Settings& s) { return py::object(py::bool_(s.read.block_delete == "on")); }};
}

#define DEFLEX_REF(expr) \
  [](Settings & s) -> auto& { return s.expr; }

const std::vector<Field>& fields() {
  static const std::vector<Field> all = {
      path_field("program", DEFLEX_REF(program)),
      path_field("output", DEFLEX_REF(output)),
      path_field("reference", DEFLEX_REF(reference)),
      path_field("report_dir", DEFLEX_REF(report_dir)),
      path_field("dialect", DEFLEX_REF(read.dialect)),
      path_field("machine", DEFLEX_REF(read.machine)),
      path_field("config", DEFLEX_REF(read.config)),
      int_field<int>("max_errors", DEFLEX_REF(read.max_errors)),
      block_delete_field(),
      bool_field("strict", DEFLEX_REF(read.strict)),
      int_field<std::uint64_t>("max_blocks", DEFLEX_REF(read.max_blocks)),
      path_field("material", DEFLEX_REF(material.material)),
      path_field("material_file", DEFLEX_REF(material.material_file)),
      optional_field("kt_N_per_mm2", DEFLEX_REF(material.kt)),
      optional_field("kr_N_per_mm2", DEFLEX_REF(material.kr)),
      optional_field("ka_N_per_mm2", DEFLEX_REF(material.ka)),
      optional_field("kte_N_per_mm", DEFLEX_REF(material.kte)),
      optional_field("kre_N_per_mm", DEFLEX_REF(material.kre)),
      optional_field("kae_N_per_mm", DEFLEX_REF(material.kae)),
      path_field("part", DEFLEX_REF(part.part)),
      optional_field("part_gap_mm", DEFLEX_REF(part.gap_mm)),
      fixture_field(),
      number_field("workpiece_mesh_mm", DEFLEX_REF(workholding.mesh_mm)),
      number_field("workpiece_spacing_mm", DEFLEX_REF(workholding.spacing_mm)),
      int_field<int>("workpiece_stages", DEFLEX_REF(workholding.stages)),
      path_field("tool_file", DEFLEX_REF(tool_file)),
      path_field("tool", DEFLEX_REF(tool)),
      path_field("stock", DEFLEX_REF(stock)),
      stock_from_field(),
      optional_field("tolerance_mm", DEFLEX_REF(tolerance_mm)),
      optional_field("gain", DEFLEX_REF(gain)),
      number_field("feed_limit_N", DEFLEX_REF(feed_limit_N)),
      optional_field("spindle_rpm", DEFLEX_REF(spindle_rpm)),
      optional_field("feed_mm_per_min", DEFLEX_REF(feed_mm_per_min)),
      number_field("cell_mm", DEFLEX_REF(cell_mm)),
      number_field("cl_spacing_mm", DEFLEX_REF(cl_spacing_mm)),
      int_field<int>("max_iterations", DEFLEX_REF(max_iterations)),
      int_field<int>("threads", DEFLEX_REF(threads)),
      bool_field("tool_only", DEFLEX_REF(tool_only)),
      bool_field("expand_subprograms", DEFLEX_REF(expand_subprograms)),
      path_field("measured", DEFLEX_REF(measured)),
      path_field("probe_program", DEFLEX_REF(probe_program)),
      number_field("measured_reach_mm", DEFLEX_REF(measured_reach_mm)),
  };
  return all;
}

#undef DEFLEX_REF

}  // namespace

std::string path_text(const char* what, py::handle v) { return text(what, v); }

void apply_keywords(Settings& s, const py::dict& kwargs) {
  for (const auto& [key, value] : kwargs) {
    const std::string name = py::str(key);
    const Field* f = nullptr;
    for (const Field& c : fields())
      if (name == c.name) f = &c;
    if (!f) throw py::type_error("deflex.Job: unknown setting '" + name + "' (deflex.Job.settings_names() lists them)");
    if (!value.is_none()) f->set(s, value);
  }
}

py::dict keywords_of(const Settings& s) {
  py::dict d;
  for (const Field& f : fields()) d[f.name] = f.get(s);
  return d;
}

}  // namespace deflex::python

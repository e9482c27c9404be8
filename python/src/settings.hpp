// job::Settings (include/deflex/job/settings.hpp) from Python keywords and back.
#pragma once
#include <pybind11/pybind11.h>

#include "deflex/job/settings.hpp"

namespace deflex::python {
namespace py = pybind11;

// Sets the fields `kwargs` names. The nested ReadSettings, MaterialSettings
// and PartSettings are flat here (machine=, material=, kt_N_per_mm2=, part=,
// part_gap_mm=, ...), the coefficients with their units in the name;
// stock_from is a list of paths or (program, tool_file) pairs. None leaves a
// field at its default. An unknown keyword or a value of the wrong type is a
// TypeError; values are checked by job::open(), as the command line's are.
void apply_keywords(job::Settings& s, const py::dict& kwargs);

// A str or an os.PathLike as a path; a TypeError naming `what` otherwise.
std::string path_text(const char* what, py::handle v);

// Every field by its keyword: what apply_keywords() takes (None: unset).
py::dict keywords_of(const job::Settings& s);

}  // namespace deflex::python

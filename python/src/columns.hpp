// points.csv as columns: the rows a job's Observer receives
// (report::PointRow, report/recorder.hpp), kept in C++ while the run goes
// (they may come from a worker thread, without the GIL), then handed to
// Python as NumPy arrays named exactly as kPointsCsvHeader's columns.
#pragma once
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <vector>

#include "deflex/report/recorder.hpp"

namespace deflex::python {
namespace py = pybind11;

class Columns {
 public:
  Columns();
  void add(const report::PointRow& r);
  std::size_t size() const { return lines_.size(); }
  // {name: array} in the header's order: line as int64, normal_source as an
  // object array of str (pandas makes it categorical with .astype("category")),
  // the rest float64 with NaN where points.csv has an empty cell. Needs the GIL.
  py::dict to_numpy() const;

 private:
  std::vector<std::string> names_;  // the header's columns
  std::vector<std::uint32_t> lines_;
  std::vector<std::string> normal_sources_;
  std::vector<std::vector<double>> values_;  // per float column of names_, in order
};

}  // namespace deflex::python

// _deflex.Job: job::Settings from keywords or a job file, and the runs of the
// job API (job/job.hpp) with the GIL released, their results as Python objects
// (deflex/results.py wraps them).
#include "deflex/job/job.hpp"

#include "deflex/job/fit.hpp"

#include <pybind11/stl.h>

#include <sstream>

#include "bindings.hpp"
#include "observer.hpp"
#include "settings.hpp"

namespace deflex::python {
namespace {

// Where a run's messages go: string streams, read after the run (the
// library writes them from the calling thread while the GIL is released).
struct Captured {
  std::istringstream in;  // a program of "-": none from Python
  std::ostringstream out, err;
  job::Io io{in, out, err};
};

// Opens the job for `purpose` and runs `body` on it without the GIL; a
// failure is raised as its Python exception with the messages printed before
// it (raise_python), an exception the progress callable or a signal handler
// raised as itself. Returns the tolerance the run used.
template <class Body>
double run_released(const job::Settings& s, job::Purpose purpose, PyObserver& obs, Captured& c, Body body) {
  std::exception_ptr failure;
  double tolerance_mm = 0;
  {
    py::gil_scoped_release nogil;
    try {
      job::Run run = job::open(s, purpose, c.io, &obs);
      body(run);
      tolerance_mm = run.settings.tolerance_mm;
    } catch (...) {
      failure = std::current_exception();
    }
  }
  if (!failure) return tolerance_mm;
  if (obs.pending()) throw std::move(*obs.pending());
  raise_python(failure, c.err.str());
}

py::dict stats_of(const report::ErrorStats& s) {
  py::dict d;
  d["points"] = s.points;
  d["max_abs_mm"] = s.max_abs;
  d["rms_mm"] = s.rms;
  d["share_outside"] = s.share_out;
  d["max_under_mm"] = s.max_under;
  d["max_over_mm"] = s.max_over;
  return d;
}

// report::RunFigures: the error (as written beside it for a compensation) and the loads.
py::dict figures_of(const report::RunFigures& f) {
  py::dict d;
  d["error"] = stats_of(f.error);
  d["error_as_written"] = stats_of(f.error_as_written);
  d["cusp_max_mm"] = f.cusp.points ? py::object(py::float_(f.cusp.max)) : py::object(py::none());
  d["cusp_mean_mm"] = f.cusp.points ? py::object(py::float_(f.cusp.mean)) : py::object(py::none());
  d["peak_force_N"] = f.peak_force_N;
  d["mean_force_N"] = f.mean_force_N;
  d["peak_deflection_mm"] = f.peak_deflection_mm;
  d["peak_mrr_mm3_per_s"] = f.peak_mrr_mm3_per_s;
  return d;
}

// What every run gives: summary.json as text (deflex/results.py parses it:
// nlohmann's dump is JSON, so json.loads gives the file's values), the
// messages, the points.
py::dict common(const report::Json& summary, const report::RunFigures& f, double tolerance_mm, const Captured& c,
                const PyObserver& obs, bool rows) {
  py::dict d;
  d["summary_json"] = summary.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  d["figures"] = figures_of(f);
  d["tolerance_mm"] = tolerance_mm;
  d["messages"] = c.err.str();
  d["points"] = rows ? py::object(obs.columns().to_numpy()) : py::object(py::none());
  return d;
}

struct Job {
  job::Settings settings;

  py::dict simulate(py::object progress, bool rows) const {
    PyObserver obs(std::move(progress), rows);
    Captured c;
    job::SimulateResult r;
    const double tol = run_released(settings, job::Purpose::simulate, obs, c,
                                    [&](job::Run& run) { r = job::simulate(run, c.io, &obs); });
    return common(r.summary, r.figures, tol, c, obs, rows);
  }

  // `output`: None (the settings' output, else the text in memory) or a path.
  py::dict compensate(py::object output, py::object progress, bool rows) const {
    job::Settings s = settings;
    if (!output.is_none()) s.output = path_text("output", output);
    if (s.output == "-") s.output.clear();
    PyObserver obs(std::move(progress), rows);
    Captured c;
    job::CompensateResult r;
    const double tol = run_released(s, job::Purpose::compensate, obs, c,
                                    [&](job::Run& run) { r = job::compensate(run, c.out, c.io, &obs); });
    py::dict d = common(r.summary, r.figures, tol, c, obs, rows);
    // Bytes, not str: the program's own bytes (CRLF, any encoding) exactly.
    d["program"] = s.output.empty() ? py::object(py::bytes(c.out.str())) : py::object(py::none());
    d["output"] = s.output.empty() ? py::object(py::none()) : py::object(py::str(s.output));
    return d;
  }
};

// job::fit of the job's program to its `measured` points: the fitted profile
// (text, or written to `output`), each parameter and the residuals.
py::dict fit_job(const Job& j, py::object output, py::object progress, double determined_within) {
  job::FitSettings s;
  s.run = j.settings;
  if (!output.is_none()) s.output = path_text("output", output);
  s.options.determined_within = determined_within;
  PyObserver obs(std::move(progress), false);
  Captured c;
  job::FitReport r;
  std::exception_ptr failure;
  {
    py::gil_scoped_release nogil;
    try {
      r = job::fit(s, c.out, c.io, &obs);
    } catch (...) {
      failure = std::current_exception();
    }
  }
  if (failure) {
    if (obs.pending()) throw std::move(*obs.pending());
    raise_python(failure, c.err.str());
  }
  py::dict params;
  for (int k = 0; k < fit::kParams; ++k) {
    const fit::ParamFit& f = r.fit.params[k];
    py::dict p;
    p["fitted"] = f.fitted;
    p["factor"] = f.fitted ? py::object(py::float_(f.scale)) : py::object(py::none());
    p["interval95"] = f.fitted ? py::object(py::make_tuple(f.lo95, f.hi95)) : py::object(py::none());
    p["at_bound"] = f.at_bound;
    p["why_held"] = f.why_held;
    params[fit::name(fit::Param(k))] = p;
  }
  py::dict features;
  for (const job::FeatureFit& f : r.features) {
    py::dict d;
    d["points"] = f.points;
    d["rms_before_mm"] = f.rms_before_mm, d["rms_after_mm"] = f.rms_after_mm;
    d["max_before_mm"] = f.max_before_mm, d["max_after_mm"] = f.max_after_mm;
    features[py::str(f.feature)] = d;
  }
  py::dict d;
  d["parameters"] = params;
  d["features"] = features;
  d["measured_points"] = r.observations;
  d["compared_points"] = r.matched;
  d["rms_before_mm"] = r.all.rms_before_mm, d["rms_after_mm"] = r.all.rms_after_mm;
  d["max_before_mm"] = r.all.max_before_mm, d["max_after_mm"] = r.all.max_after_mm;
  d["sigma_mm"] = r.fit.sigma_mm;
  d["profile"] = r.profile_text;
  d["output"] = s.output.empty() || s.output == "-" ? py::object(py::none()) : py::object(py::str(s.output));
  d["messages"] = c.err.str();
  return d;
}

Job from_file(py::handle file, const py::kwargs& overrides) {
  Job j;
  apply_keywords(j.settings, overrides);
  // The keywords win over the file, as the command line does (settings.hpp).
  std::vector<std::string> programs;
  if (!j.settings.program.empty()) programs.push_back(j.settings.program);
  job::apply_job_file(path_text("file", file), j.settings, programs);
  if (!programs.empty()) j.settings.program = programs.front();
  return j;
}

}  // namespace

void bind_job(py::module_& m) {
  py::class_<Job>(m, "Job")
      .def(py::init([](const py::kwargs& kw) {
        Job j;
        apply_keywords(j.settings, kw);
        return j;
      }))
      .def_static("from_file", &from_file, py::arg("file"))
      .def_property_readonly("settings", [](const Job& j) { return keywords_of(j.settings); })
      .def("simulate", &Job::simulate, py::arg("progress") = py::none(), py::arg("rows") = true)
      .def("compensate", &Job::compensate, py::arg("output") = py::none(), py::arg("progress") = py::none(),
           py::arg("rows") = true)
      .def("fit", &fit_job, py::arg("output") = py::none(), py::arg("progress") = py::none(),
           py::arg("determined_within") = 0.10);
}

}  // namespace deflex::python

// deflex fit: a machine profile fitted to a measured cut (job::fit), its
// parameters, intervals, correlations and residuals printed.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/job/fit.hpp"

namespace deflex::cli {
namespace {

const char* kFitHelp =
    "Fits the machine profile to what was measured on a part the program cut - the\n"
    "test cut of `deflex testcut`, probed on the machine with `deflex probe`, or any\n"
    "program whose part was measured: the stiffness of the tool clamp, the spindle and\n"
    "the structure along X, Y and Z, each as a factor of the starting profile's\n"
    "(--machine), and a factor of the material's force coefficients (the profile's\n"
    "force_scale). The program is simulated once per stiffness term (the error is\n"
    "linear in each compliance and in the force); Ceres then solves the bounded least\n"
    "squares of predicted - measured error at the measured points.\n"
    "A parameter the measured points do not feel (no measured wall faces its axis) or\n"
    "cannot tell from another (from walls of one tool, the clamp and the spindle are\n"
    "twins, and force and compliance trade off) is held at the starting profile's\n"
    "value and named, with the parameter it trades off against: it is never invented.\n"
    "The 95 % intervals assume the held values are right; where they are not, the\n"
    "fitted ones absorb them, and the profile then predicts the tools of the measured\n"
    "cut. The fitted profile (-o, default stdout) is the starting one with its numbers\n"
    "replaced where they stand and the fit's provenance in comments at its head.\n"
    "Measurements (--measured): a CSV x_mm,y_mm,z_mm of surface points (stylus radius\n"
    "removed, as CMM software exports them), a point cloud (.ply, .stl), or a probe log\n"
    "(LinuxCNC's PROBEOPEN file, or a Fanuc's DPRNT output) with --probe-program.\n"
    "The measured error is the signed distance from the intended surface along its\n"
    "normal (> 0: material left): --part where given, else the surface the program\n"
    "cuts with a rigid tool. --also adds another measured cut (a job file): the test\n"
    "cuts of two or three tools of different stick-out, fitted together, determine\n"
    "what the walls of one tool cannot. Then:\n"
    "  deflex compensate part.nc --machine fitted.yaml ...\n";

std::string n_per_um(const std::optional<double>& n_per_mm) {
  return n_per_mm ? fixed_decimals(*n_per_mm / 1000, 1) + " N/um" : "rigid";
}

// The value each parameter scales, for the table (its radial spring, its stiffness, the force scale).
std::string start_value(const job::FitReport& r, fit::Param p, bool fitted) {
  const stiffness::MachineStiffness& m = fitted ? r.fitted : r.start;
  switch (p) {
    case fit::Param::clamp: return m.tool_clamp ? n_per_um(m.tool_clamp->radial_N_per_mm) + " radial" : "rigid";
    case fit::Param::spindle: return m.spindle ? n_per_um(m.spindle->radial_N_per_mm) + " radial" : "rigid";
    case fit::Param::structure_x:
    case fit::Param::structure_y:
    case fit::Param::structure_z: {
      const int a = int(p) - int(fit::Param::structure_x);
      const double c = m.structure_mm_per_N(a, a);
      return c > 0 ? fixed_decimals(1 / c / 1000, 1) + " N/um" : "rigid";
    }
    case fit::Param::coefficients: {
      const double f = r.start_force_scale * (fitted ? r.fit.params[int(p)].scale : 1.0);
      return "force_scale " + fixed_decimals(f, 3);
    }
  }
  return "";
}

void print_fit(const job::FitReport& r, Io& io) {
  std::ostream& o = io.info();
  o << "fit: " << r.matched << " of " << plural(r.observations, "measured point") << " compared; |predicted - measured| rms "
    << fixed_decimals(r.all.rms_before_mm * 1000, 2) << " -> " << fixed_decimals(r.all.rms_after_mm * 1000, 2) << " um, max "
    << fixed_decimals(r.all.max_before_mm * 1000, 2) << " -> " << fixed_decimals(r.all.max_after_mm * 1000, 2) << " um\n";
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-20s %-22s %-22s %s\n", "parameter", "starting profile", "fitted", "factor (95 % interval)");
  o << buf;
  for (int k = 0; k < fit::kParams; ++k) {
    const fit::ParamFit& f = r.fit.params[k];
    const fit::Param p = fit::Param(k);
    std::string factor = f.fitted ? "x" + fixed_decimals(f.scale, 3) + " (x" + fixed_decimals(f.lo95, 3) + " to x" +
                                        fixed_decimals(f.hi95, 3) + ")" + (f.at_bound ? " at its bound" : "")
                                  : "held";
    std::snprintf(buf, sizeof buf, "  %-20s %-22s %-22s %s\n", fit::name(p), start_value(r, p, false).c_str(),
                  f.fitted ? start_value(r, p, true).c_str() : "(as the profile)", factor.c_str());
    o << buf;
  }
  for (int k = 0; k < fit::kParams; ++k)
    if (!r.fit.params[k].fitted) o << "  held: " << fit::name(fit::Param(k)) << ": " << r.fit.params[k].why_held << "\n";
  std::ostringstream corr;
  for (int a = 0; a < fit::kParams; ++a)
    for (int b = a + 1; b < fit::kParams; ++b)
      if (std::isfinite(r.fit.correlation(a, b)))
        corr << "  " << fit::name(fit::Param(a)) << " / " << fit::name(fit::Param(b)) << " " << fixed_decimals(r.fit.correlation(a, b), 2) << "\n";
  if (!corr.str().empty()) o << "correlations of the fitted parameters:\n" << corr.str();
  o << "residual per feature (|predicted - measured|, um):\n";
  for (const job::FeatureFit& f : r.features) {
    std::snprintf(buf, sizeof buf, "  %-12s %6zu points  rms %6.2f -> %6.2f  max %6.2f -> %6.2f\n",
                  f.feature.empty() ? "(no feature)" : f.feature.c_str(), f.points, f.rms_before_mm * 1000,
                  f.rms_after_mm * 1000, f.max_before_mm * 1000, f.max_after_mm * 1000);
    o << buf;
  }
}

}  // namespace

int cmd_fit(const std::vector<std::string>& args, Io& io) {
  job::FitSettings s;
  bool help = false;
  std::string job_file;
  po::options_description desc("options");
  describe(desc, s.run, help, job_file, false);
  std::vector<std::string> also;
  desc.add_options()("output,o", po::value(&s.output), "write the fitted machine profile here (atomically); default stdout")(
      "also", po::value(&also)->composing(),
      "another measured cut of the same machine, fitted together with PROGRAM: a job file (YAML: program, tool, stock, "
      "measured, probe_program; what it leaves out is this command line's, the tool the program's T words). Repeat it. Test cuts of tools that stick out "
      "differently tell the clamp, the spindle and the force scale apart where one tool cannot")(
      "determined-within", po::value(&s.options.determined_within)->default_value(0.10, "0.10"),
      "a parameter whose 95 % interval reaches beyond x(1 + this) is held, not fitted");
  std::vector<std::string> files;
  parse_with_files(args, desc, files, 1);
  if (!job_file.empty()) job::apply_job_file(job_file, s.run, files);
  if (help) {
    print_help(io.out,
               "deflex fit PROGRAM --measured FILE [--probe-program probe.nc] --machine M [--tool-file F] [--material M] "
               "--stock S [--also CUT2.yaml ...] [-o fitted.yaml]",
               kFitHelp, desc);
    return 0;
  }
  if (files.empty()) throw Error(ErrorKind::settings, "fit: the program whose cut was measured is required (see deflex fit --help)");
  if (!s.run.reference.empty() || !s.run.report_dir.empty())
    throw Error(ErrorKind::settings, "fit: --reference and --report have no meaning here (simulate --measured --report shows predicted against measured)");
  s.run.program = files[0];
  for (const std::string& job : also) {
    job::Settings more = s.run;  // material, libraries, tolerance ... as given here
    more.program.clear(), more.measured.clear(), more.probe_program.clear(), more.tool.clear(), more.stock.clear();
    std::vector<std::string> programs;
    job::apply_job_file(job, more, programs);
    if (more.stock.empty()) more.stock = s.run.stock;  // the same block unless the job file says
    if (programs.empty()) throw Error(ErrorKind::settings, job + ": error: --also needs a job file naming its program");
    more.program = programs.front();
    s.more.push_back(std::move(more));
  }
  ProgressLine progress(io);
  const job::FitReport r = job::fit(s, io.out, io, &progress);
  print_fit(r, io);
  return 0;
}

}  // namespace deflex::cli

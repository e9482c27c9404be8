// job::fit() (fit.hpp): measurements, basis simulations, the fit, the profile.
#include "deflex/job/fit.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <sstream>

#include "deflex/diag/plural.hpp"
#include "deflex/fit/basis.hpp"
#include "deflex/job/job.hpp"
#include "deflex/job/run.hpp"
#include "deflex/version.hpp"
#include "deflex/writer/writer.hpp"
#include "internal.hpp"

namespace deflex::job {

namespace {

void check(const FitSettings& s) {
  if (!s.output.empty() && s.output != "-") writer::check_output_path(s.output, s.run.program);
  if (!(s.run.measured_reach_mm > 0 && s.run.measured_reach_mm <= 10))
    throw Error(ErrorKind::settings, "{measured_reach_mm} must be above 0 and at most 10 mm (got " + fixed_decimals(s.run.measured_reach_mm, 3) + ")");
  const fit::FitOptions& o = s.options;
  if (!(o.min_scale > 0 && o.min_scale < 1 && o.max_scale > 1) || !(o.min_coefficients > 0 && o.min_coefficients < 1 && o.max_coefficients > 1))
    throw Error(ErrorKind::settings, "the fit's bounds must lie below and above 1 (the starting profile)");
  if (!(o.determined_within > 0))
    throw Error(ErrorKind::settings, "the fit's determinacy limit must be above 0");
  if (s.run.tool_only)
    throw Error(ErrorKind::settings, "{tool_only} leaves the machine out of the deflection: there is nothing to fit");
}

void add_residual(FeatureFit& f, double before, double after) {
  ++f.points;
  f.rms_before_mm += before * before, f.rms_after_mm += after * after;
  f.max_before_mm = std::max(f.max_before_mm, std::abs(before));
  f.max_after_mm = std::max(f.max_after_mm, std::abs(after));
}

void finish(FeatureFit& f) {
  if (!f.points) return;
  f.rms_before_mm = std::sqrt(f.rms_before_mm / static_cast<double>(f.points));
  f.rms_after_mm = std::sqrt(f.rms_after_mm / static_cast<double>(f.points));
}

void feature_fits(FitReport& r, const std::vector<fit::Observation>& obs, const fit::Matching& m) {
  std::map<std::string, FeatureFit> by;
  for (std::size_t i = 0; i < m.matched.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const double before = r.fit.residual_before_mm(k), after = r.fit.residual_mm(k);
    FeatureFit& f = by[obs[m.matched[i].observation].feature];
    f.feature = obs[m.matched[i].observation].feature;
    add_residual(f, before, after);
    add_residual(r.all, before, after);
  }
  for (auto& [name, f] : by) {
    finish(f);
    r.features.push_back(f);
  }
  finish(r.all);
}

std::string sig(double v, int digits = 4) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

// The comment lines at the head of the fitted profile: what was fitted from what.
std::vector<std::string> provenance(const FitSettings& s, const Run& run, const FitReport& r) {
  std::vector<std::string> p;
  p.push_back("Fitted by deflex " DEFLEX_VERSION " (deflex fit) from the program " + s.run.program + " and the measurements " +
              s.run.measured + (s.run.probe_program.empty() ? "" : " (probe program " + s.run.probe_program + ")") + ".");
  p.push_back("Starting profile: " + run.setup.machine->file + "; material " + run.material + ".");
  p.push_back(std::to_string(r.matched) + " of " + std::to_string(r.observations) + " measured points compared; " +
              "|predicted - measured| rms " + fixed_decimals(r.all.rms_before_mm * 1000, 2) + " um before, " +
              fixed_decimals(r.all.rms_after_mm * 1000, 2) + " um after (max " + fixed_decimals(r.all.max_before_mm * 1000, 2) +
              " -> " + fixed_decimals(r.all.max_after_mm * 1000, 2) + " um).");
  p.push_back("The intervals assume that what is held is right; a held value the machine does not have is absorbed "
              "by the fitted ones, which then predict the tools of the measured cut, not others.");
  for (int k = 0; k < fit::kParams; ++k) {
    const fit::ParamFit& f = r.fit.params[k];
    const std::string n = fit::name(fit::Param(k));
    if (f.fitted)
      p.push_back(n + ": x" + sig(f.scale) + " of the starting value, 95 % interval x" + sig(f.lo95) + " to x" + sig(f.hi95) +
                  (f.at_bound ? " (at the fit's bound: check the profile)" : ""));
    else
      p.push_back(n + ": as in the starting profile; " + f.why_held);
  }
  return p;
}

}  // namespace

namespace {

FitReport fit_run(const FitSettings& s, Run& run, const std::vector<fit::Observation>& obs, std::ostream& out, Io& io,
                  Observer* observer) {
  const compensate::Progress progress = detail::progress_of(observer);
  const fit::Basis b = fit::simulate_basis(run.motions, run.physics, run.settings, tool_of(run), progress);
  detail::end_progress(progress);
  const fit::Matching m = fit::match(b.surface, obs, s.run.measured_reach_mm, run.part.get());

  FitReport r;
  r.observations = obs.size();
  r.matched = m.matched.size();
  for (std::size_t i : m.unmatched) r.unmatched.push_back(obs[i].source);
  if (!m.unmatched.empty())
    io.err << (obs[m.unmatched.front()].source.empty() ? s.run.measured : obs[m.unmatched.front()].source)
           << ": warning: " << plural(m.unmatched.size(), "measured point") << " of " << obs.size() << " lie farther than "
           << fixed_decimals(s.run.measured_reach_mm, 3) << " mm from the surface " << s.run.program
           << " cuts: left out of the fit (is the work offset, or the program, the one measured?)\n";
  r.fit = fit::solve(b, m, s.options);
  feature_fits(r, obs, m);
  r.start = run.physics.machine;
  r.fitted = fit::scaled(run.physics.machine, r.fit.scales);
  r.start_force_scale = run.setup.machine->force_scale;
  fit::Scales written = r.fit.scales;
  written[int(fit::Param::coefficients)] *= r.start_force_scale;
  r.profile_text = fitted_profile_text(run.setup.machine->file, written, provenance(s, run, r));
  if (s.output.empty() || s.output == "-")
    out << r.profile_text;
  else
    writer::write_file_atomically(s.output, s.run.program, [&](std::ostream& o) { o << r.profile_text; });
  return r;
}

}  // namespace

FitReport fit(const FitSettings& s, std::ostream& out, Io& io, Observer* observer) {
  check(s);
  if (s.run.measured.empty()) throw Error(ErrorKind::settings, "fit: give the measurements ({measured})");
  Run run = open(s.run, Purpose::fit, io, observer);
  return fit_run(s, run, run.measured, out, io, observer);
}

FitReport fit(const FitSettings& s, const std::vector<fit::Observation>& obs, std::ostream& out, Io& io,
              Observer* observer) {
  check(s);
  if (obs.empty()) throw Error(ErrorKind::settings, "no measured points: there is nothing to fit");
  FitSettings given = s;
  given.run.measured.clear();  // the observations are given: no file to read
  Run run = open(given.run, Purpose::fit, io, observer);
  return fit_run(s, run, obs, out, io, observer);
}

}  // namespace deflex::job

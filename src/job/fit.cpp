// job::fit() (fit.hpp): measurements, basis simulations, the fit, the profile.
#include "deflex/job/fit.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
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
}

// What each measured cut needs: its measurements, and the machine in its deflection.
void check_cut(const Settings& c) {
  if (c.measured.empty()) throw Error(ErrorKind::settings, "fit: " + c.program + " has no measurements ({measured})");
  if (c.tool_only)
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

// One measured cut: its run, its points, its basis and their matching.
struct CutData {
  Run run;
  std::vector<fit::Observation> obs;
  std::unique_ptr<fit::Basis> basis;
  fit::Matching matching;
};

// The residuals per feature; with several cuts a feature is named with its
// program's file name (and the tool given for it).
void feature_fits(FitReport& r, const std::vector<CutData>& cuts) {
  std::map<std::string, FeatureFit> by;
  Eigen::Index k = 0;
  for (const CutData& c : cuts)
    for (const fit::Matched& m : c.matching.matched) {
      const double before = r.fit.residual_before_mm(k), after = r.fit.residual_mm(k);
      ++k;
      const std::string& feature = c.obs[m.observation].feature;
      const Settings& g = c.run.given;
      const std::string cut = std::filesystem::path(g.program).filename().string() + (g.tool.empty() ? "" : " " + g.tool);
      const std::string name = cuts.size() > 1 ? cut + (feature.empty() ? "" : " " + feature) : feature;
      FeatureFit& f = by[name];
      f.feature = name;
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
  auto cut = [](const Settings& c) {
    return c.program + " measured by " + c.measured + (c.probe_program.empty() ? "" : " (probe program " + c.probe_program + ")");
  };
  std::string from = cut(s.run);
  for (const Settings& c : s.more) from += "; " + cut(c);
  p.push_back("Fitted by deflex " DEFLEX_VERSION " (deflex fit) from " + from + ".");
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

// Simulates each cut once per basis machine, matches its points, and fits them together.
FitReport fit_cuts(const FitSettings& s, std::vector<CutData>& cuts, std::ostream& out, Io& io, Observer* observer) {
  const compensate::Progress progress = detail::progress_of(observer);
  FitReport r;
  std::vector<fit::Cut> parts;
  for (CutData& c : cuts) {
    c.basis = std::make_unique<fit::Basis>(
        fit::simulate_basis(c.run.motions, c.run.physics, c.run.settings, tool_of(c.run), progress));
    c.matching = fit::match(c.basis->surface, c.obs, s.run.measured_reach_mm, c.run.part.get());
    r.observations += c.obs.size();
    r.matched += c.matching.matched.size();
    for (std::size_t i : c.matching.unmatched) r.unmatched.push_back(c.obs[i].source);
    if (!c.matching.unmatched.empty())
      io.err << (c.obs[c.matching.unmatched.front()].source.empty() ? c.run.given.measured
                                                                     : c.obs[c.matching.unmatched.front()].source)
             << ": warning: " << plural(c.matching.unmatched.size(), "measured point") << " of " << c.obs.size()
             << " lie farther than " << fixed_decimals(s.run.measured_reach_mm, 3) << " mm from the surface "
             << c.run.given.program << " cuts: left out of the fit (is the work offset, or the program, the one measured?)\n";
    parts.push_back({c.basis.get(), &c.matching});
  }
  detail::end_progress(progress);
  const Run& run = cuts.front().run;
  r.fit = fit::solve(parts, s.options);
  if (!r.fit.converged)
    io.err << run.given.program << ": warning: the fit did not converge (Ceres: " << r.fit.message
           << "): the factors are where it stopped, not a minimum\n";
  feature_fits(r, cuts);
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

// The more cuts (checked by check_cut()), opened after the first: each on the first's machine.
void open_more(const FitSettings& s, std::vector<CutData>& cuts, Io& io, Observer* observer) {
  for (const Settings& more : s.more) {
    Settings m = more;
    m.read.machine = s.run.read.machine;
    m.measured_reach_mm = s.run.measured_reach_mm;
    CutData c{open(m, Purpose::fit, io, observer), {}, nullptr, {}};
    c.obs = std::move(c.run.measured);
    cuts.push_back(std::move(c));
  }
}

}  // namespace

FitReport fit(const FitSettings& s, std::ostream& out, Io& io, Observer* observer) {
  check(s);
  if (s.run.measured.empty()) throw Error(ErrorKind::settings, "fit: give the measurements ({measured})");
  check_cut(s.run);
  for (const Settings& m : s.more) check_cut(m);
  std::vector<CutData> cuts;
  cuts.push_back({open(s.run, Purpose::fit, io, observer), {}, nullptr, {}});
  cuts.back().obs = std::move(cuts.back().run.measured);
  open_more(s, cuts, io, observer);
  return fit_cuts(s, cuts, out, io, observer);
}

FitReport fit(const FitSettings& s, const std::vector<fit::Observation>& obs, std::ostream& out, Io& io,
              Observer* observer) {
  check(s);
  if (obs.empty()) throw Error(ErrorKind::settings, "no measured points: there is nothing to fit");
  if (s.run.tool_only)
    throw Error(ErrorKind::settings, "{tool_only} leaves the machine out of the deflection: there is nothing to fit");
  for (const Settings& m : s.more) check_cut(m);
  FitSettings given = s;
  given.run.measured.clear();  // the observations are given: no file to read
  std::vector<CutData> cuts;
  cuts.push_back({open(given.run, Purpose::fit, io, observer), obs, nullptr, {}});
  open_more(s, cuts, io, observer);
  return fit_cuts(s, cuts, out, io, observer);
}

}  // namespace deflex::job

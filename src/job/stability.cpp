// job::stability() (stability.hpp).
#include "deflex/job/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/force/cutter.hpp"
#include "deflex/force/tool.hpp"
#include "deflex/job/setup.hpp"
#include "deflex/profile/profile.hpp"
#include "deflex/stability/model.hpp"
#include "deflex/stiffness/machine.hpp"

namespace deflex::job {
namespace {

namespace st = deflex::stiffness;

void check(const StabilitySettings& s) {
  if (s.tool.empty()) throw Error(ErrorKind::settings, "stability: give the tool (--tool)");
  if (!(s.ae_mm > 0) || !std::isfinite(s.ae_mm)) throw Error(ErrorKind::settings, "the radial depth of cut a_e must be > 0 mm");
  if (s.ap_mm && (!(*s.ap_mm > 0) || !std::isfinite(*s.ap_mm)))
    throw Error(ErrorKind::settings, "the axial depth of cut a_p must be > 0 mm");
  if (s.rpm_min != 0 || s.rpm_max != 0)
    if (!(s.rpm_min > 0 && s.rpm_max > s.rpm_min) || !std::isfinite(s.rpm_max))
      throw Error(ErrorKind::settings, "the speed range must be 0 < MIN < MAX rpm");
  if (s.points < 10 || s.points > 1000000) throw Error(ErrorKind::settings, "the points of the limit must be 10 to 1000000");
  if (!s.frf.empty() && s.machine.empty() && !(s.rpm_max > 0))
    throw Error(ErrorKind::settings, "stability: with a measured FRF and no machine profile, give the speed range (--rpm MIN:MAX)");
}

// The mean directional coefficients of the cut: the textbook immersion of
// a_e, or the engagement of a_e and a_p on the tool's own shape.
Eigen::Matrix2d mean_alpha(const StabilitySettings& s, const st::Tool& t, const force::Coefficients& k,
                           force::AngleInterval immersion) {
  if (!s.ap_mm) return stability::directional_coefficients(stability::cut_of(k, t.flutes, immersion));
  const force::Cutter c = force::cutter_of(t);
  if (*s.ap_mm > c.flute_length_mm)
    throw Error(ErrorKind::settings, "the axial depth of cut a_p exceeds the flute length of tool " + t.id);
  const force::CutterSlices cs = force::make_slices(c, std::min(0.05, *s.ap_mm / 20), *s.ap_mm);
  force::Engagement e;
  force::simple_engagement(cs, s.ae_mm, *s.ap_mm, s.up_milling ? force::MillingMode::up : force::MillingMode::down, e);
  const Eigen::Matrix2d B = stability::directional_matrix_mm(cs, e, k);
  if (B.isZero()) {
    char b[300];
    std::snprintf(b, sizeof b,
                  "stability: a cut %g mm wide (a_e, from the full diameter) and %g mm deep engages nothing of %s: "
                  "its radius at that depth does not reach the wall",
                  s.ae_mm, *s.ap_mm, t.id.c_str());
    throw Error(ErrorKind::settings, b);
  }
  return B / *s.ap_mm;
}

// The envelope's local maxima (plateaus counted once), highest first.
std::vector<std::pair<double, double>> pockets(const std::vector<std::pair<double, double>>& limit) {
  std::vector<std::pair<double, double>> p;
  for (std::size_t i = 1; i + 1 < limit.size(); ++i)
    if (limit[i].second > limit[i - 1].second && limit[i].second >= limit[i + 1].second) p.push_back(limit[i]);
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  return p;
}

}  // namespace

StabilityResult stability(const StabilitySettings& s) {
  check(s);
  const profile::Config cfg = profile::load_config();
  MaterialSettings mat = s.material;
  if (!mat.material.empty() || !mat.kt) mat.material_file = material_library_path(mat.material_file, cfg);
  force::Coefficients k = coefficients_of(mat, config_string(cfg, "material"));
  const std::string lib = !s.tool_file.empty() ? s.tool_file : tool_library_path("", cfg);
  StabilityResult r;
  r.tool = st::find_tool(st::load_tool_library(lib), s.tool);
  r.material = !mat.material.empty() ? mat.material : mat.kt ? "the coefficients given" : config_string(cfg, "material");
  double max_rpm = 0;
  st::MachineStiffness m;
  // The model needs a machine (its holder, joints and damping) unless the
  // tool alone is asked for; a measured FRF only its speed range, if any.
  const std::string machine = !s.machine.empty() || !s.frf.empty() || s.tool_only ? s.machine : cfg.machine;
  if (s.frf.empty() && !s.tool_only && machine.empty())
    throw Error(ErrorKind::settings, "stability: give a machine profile (--machine, or machine: in the config), a measured FRF (--frf) or --tool-only");
  if (!machine.empty()) {
    const profile::MachineProfile mp = profile::load_machine(machine);
    r.machine_file = mp.file;
    k = force::scaled(k, mp.force_scale);  // the machine's fitted forces, as a run takes them
    if (mp.spindle.set) max_rpm = mp.spindle.max_rpm;
    m = st::load_machine_stiffness(mp.file);
  }
  stability::Frf frf;
  if (!s.frf.empty()) {
    frf = stability::load_frf_csv(s.frf);
  } else {
    const stability::TipModel tip = stability::tip_model(r.tool, m, s.tool_only);
    r.modes = tip.modes;
    r.damping_given = m.dynamics.damping_given;
    frf = tip.frf;
  }
  r.frf_source = frf.source;
  if (s.rpm_max > 0) {
    r.rpm_min = s.rpm_min, r.rpm_max = s.rpm_max;
  } else {
    std::tie(r.rpm_min, r.rpm_max) = stability::rpm_range(max_rpm > 0 ? max_rpm : 30000);
  }
  r.immersion = force::immersion_interval(0.5 * r.tool.diameter_mm, 0.5 * r.tool.diameter_mm, s.ae_mm,
                                          s.up_milling ? force::MillingMode::up : force::MillingMode::down);
  r.Kt_N_per_mm2 = k.Ktc_N_per_mm2;
  r.Kr_ratio = stability::cut_of(k, r.tool.flutes, r.immersion).Kr_ratio;
  r.alpha = mean_alpha(s, r.tool, k, r.immersion);
  r.lobes = stability::zero_order_lobes(frf, r.alpha.cast<std::complex<double>>(), r.tool.flutes, r.Kt_N_per_mm2,
                                        r.rpm_min, r.rpm_max);
  const stability::StabilityLimit lim(r.lobes, r.rpm_min, r.rpm_max, std::max(4000, s.points));
  for (int i = 0; i <= s.points; ++i) {
    const double rpm = r.rpm_min + (r.rpm_max - r.rpm_min) * i / s.points;
    r.limit.emplace_back(rpm, lim.ap_limit_mm(rpm));
  }
  r.pockets = pockets(r.limit);
  return r;
}

}  // namespace deflex::job

// The calibration test cut: plan and program (plan/testcut.hpp).
#include "deflex/plan/testcut.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <sstream>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/force/morelli.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::plan {
namespace {

// Values on the program's grid (0.001 mm): the plan then states exactly what
// the program cuts, in every dialect (all write 3 decimals or more).
double on_grid(double v) { return std::round(v * 1000) / 1000; }

double largest(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

// a_p of each entry of o.ap_pitches: at most 90 % of the flute length (the
// shank must not rub the wall), or 1.5 D when the flute length is unknown.
std::vector<double> axial_depths(const TestCutter& t, const TestCutOptions& o) {
  const double cap = t.flute_length_mm > 0 ? 0.9 * t.flute_length_mm : 1.5 * t.diameter_mm;
  std::vector<double> ap;
  for (double f : o.ap_pitches) ap.push_back(on_grid(std::min(cap, f * axial_pitch_mm(t))));
  return ap;
}

std::vector<double> radial_depths(const TestCutter& t, const TestCutOptions& o) {
  std::vector<double> ae;
  for (double f : o.ae_fractions) ae.push_back(on_grid(f * t.diameter_mm));
  return ae;
}

// Length along a face from its free end to the far end of the last segment:
// lead (the corner kept free), n segments, n - 1 spaces, the last cutter's reach.
double face_length_mm(const TestCutter& t, const TestCutOptions& o, double ae_max) {
  const double R = t.diameter_mm / 2, n = static_cast<double>(o.ae_fractions.size() * o.ap_pitches.size());
  const double seg = o.probe_length_mm + 2 * R;
  return (ae_max + o.gap_mm + R) + n * seg + (n - 1) * (2 * R + o.gap_mm) + R + o.gap_mm;
}

std::string morelli_code(const TestCutter& t, const TestCutOptions& o, double ae, double ap) {
  force::MorelliInput in;
  in.diameter_mm = t.diameter_mm;
  in.helix_deg = t.helix_deg;
  in.flutes = t.flutes;
  in.ar_mm = ae;
  in.ap_mm = ap;
  in.Ktc_N_per_mm2 = o.Ktc_N_per_mm2;
  in.Krc_N_per_mm2 = o.Krc_N_per_mm2;
  try {
    return force::morelli_shape_code(in);
  } catch (const Error&) {
    return "";  // outside the classification (e.g. no helix)
  }
}

// One wall: the segment's tool-centre coordinates along the feed are
// [s0, s1]; the probe region is one radius in from each end.
WallFeature wall(const TestBlock& b, const TestCutter& t, const TestCutOptions& o, int axis, int number, double s0,
                 double ae, double ap) {
  const double R = t.diameter_mm / 2, top = b.z1_mm, floor = on_grid(top - ap);
  const double s1 = on_grid(s0 + o.probe_length_mm + 2 * R), clear = top + o.clearance_mm;
  WallFeature f;
  f.id = std::string("W") + (axis == 0 ? "X" : "Y") + std::to_string(number);
  f.feed_axis = axis;
  f.ae_mm = ae;
  f.ap_mm = ap;
  f.fz_mm = o.fz_mm;
  f.u0_mm = on_grid(s0 + R);
  f.u1_mm = on_grid(s1 - R);
  f.z0_mm = floor + (t.type == stock::EndShape::bull ? t.corner_radius_mm : 0.0);
  f.z1_mm = top;
  f.morelli = morelli_code(t, o, ae, ap);
  const double mid = on_grid((f.u0_mm + f.u1_mm) / 2);
  if (axis == 0) {  // back face y = Y1, material at -Y
    const double wall = on_grid(b.y1_mm - ae), centre = on_grid(wall + R), out = on_grid(b.y1_mm + R + o.air_mm);
    f.feed_direction = {1, 0, 0};
    f.normal = {0, 1, 0};
    f.point_mm = {mid, wall, top};
    f.path = {{s0, out, clear}, {s0, out, floor}, {s0, centre, floor}, {s1, centre, floor}, {s1, out, floor}, {s1, out, clear}};
  } else {  // left face x = X0, material at +X
    const double wall = on_grid(b.x0_mm + ae), centre = on_grid(wall - R), out = on_grid(b.x0_mm - R - o.air_mm);
    f.feed_direction = {0, 1, 0};
    f.normal = {-1, 0, 0};
    f.point_mm = {wall, mid, top};
    f.path = {{out, s0, clear}, {out, s0, floor}, {centre, s0, floor}, {centre, s1, floor}, {out, s1, floor}, {out, s1, clear}};
  }
  return f;
}

// The walls of one face, every a_e at every a_p, the first segment starting
// at s (tool centre along the feed), each the next segment's reach apart.
void add_face(TestCutPlan& p, const TestBlock& b, const TestCutter& t, const TestCutOptions& o, int axis, double s) {
  const double step = o.probe_length_mm + 2 * t.diameter_mm + o.gap_mm;
  int n = 0;
  for (double d : axial_depths(t, o))
    for (double w : radial_depths(t, o)) {
      p.features.push_back(wall(b, t, o, axis, ++n, s, w, d));
      s = on_grid(s + step);
    }
}

}  // namespace

double axial_pitch_mm(const TestCutter& t) {
  const double tan_helix = std::tan(t.helix_deg * std::numbers::pi / 180);
  return std::numbers::pi * t.diameter_mm / (t.flutes * tan_helix);
}

Vec3 smallest_block_mm(const TestCutter& t, const TestCutOptions& o) {
  const double ae_max = largest(radial_depths(t, o)), ap_max = largest(axial_depths(t, o));
  const double face = face_length_mm(t, o, ae_max);
  return {std::ceil(face), std::ceil(face), std::ceil(ap_max + o.floor_margin_mm)};
}

void check_testcut(const TestBlock& b, const TestCutter& t, const TestCutOptions& o) {
  auto bad = [](const std::string& what) { throw Error(ErrorKind::settings, what); };
  if (t.type == stock::EndShape::ball)
    bad("testcut: " + t.id + " is a ball end mill: the slope patches a ball needs are not implemented yet "
        "(use a flat or bull-nose end mill)");
  if (!(t.diameter_mm > 0)) bad("testcut: " + t.id + " has no diameter");
  if (t.flutes < 1) bad("testcut: " + t.id + " has no flutes");
  if (!(t.helix_deg > 0 && t.helix_deg < 80))
    bad("testcut: " + t.id + "'s helix must be in (0, 80) deg: the axial depths are chosen against the axial pitch between flutes");
  if (o.tool_number < 0 || o.tool_number > 99999) bad("testcut: the tool number must be in 0..99999");
  if (!(o.spindle_rpm > 0 && o.spindle_rpm <= 1e5)) bad("{spindle_rpm} must be in (0, 100000] rpm");
  if (!(o.fz_mm > 0 && o.fz_mm <= 1)) bad("{fz_mm} must be in (0, 1] mm per tooth");
  if (!(o.fz_mm * t.flutes * o.spindle_rpm <= 1e5)) bad("{feed_mm_per_min} must be at most 100000 mm/min");
  if (o.ae_fractions.empty() || o.ap_pitches.empty()) bad("testcut: no radial or no axial depth given");
  for (double f : o.ae_fractions)
    if (!(f > 0 && f <= 0.5)) bad("testcut: each radial depth must be in (0, 0.5] D: a wider cut is no longer a side cut of one face");
  for (double f : o.ap_pitches)
    if (!(f > 0 && f <= 5)) bad("testcut: each axial depth must be in (0, 5] axial pitches");
  for (double ap : axial_depths(t, o))
    if (!(ap > t.corner_radius_mm + 0.5))
      bad("testcut: an axial depth of " + fixed_decimals(ap, 3) + " mm leaves no wall above " + t.id + "'s corner radius");
  if (!(o.probe_length_mm >= 1 && o.probe_length_mm <= 100)) bad("testcut: the probe region must be 1 to 100 mm long");
  if (!(o.gap_mm >= 0.5 && o.air_mm >= 0.5 && o.clearance_mm >= 1 && o.floor_margin_mm >= 0))
    bad("testcut: gap and air at least 0.5 mm, clearance at least 1 mm");
  if (!(b.x1_mm > b.x0_mm && b.y1_mm > b.y0_mm && b.z1_mm > b.z0_mm)) bad("testcut: the block is empty");
  const Vec3 need = smallest_block_mm(t, o);
  if (b.x1_mm - b.x0_mm < need[0] || b.y1_mm - b.y0_mm < need[1] || b.z1_mm - b.z0_mm < need[2]) {
    std::ostringstream m;
    m << "{stock}: the block (" << significant_digits(b.x1_mm - b.x0_mm) << " x " << significant_digits(b.y1_mm - b.y0_mm)
      << " x " << significant_digits(b.z1_mm - b.z0_mm) << " mm) is too small for the test cut of " << t.id
      << ": the smallest block that fits is " << need[0] << " x " << need[1] << " x " << need[2]
      << " mm (X x Y x Z), e.g. box:" << significant_digits(b.x0_mm) << "," << significant_digits(b.y0_mm) << ","
      << significant_digits(b.z1_mm - need[2]) << "," << significant_digits(b.x0_mm + need[0]) << ","
      << significant_digits(b.y0_mm + need[1]) << "," << significant_digits(b.z1_mm);
    bad(m.str());
  }
}

TestCutPlan plan_testcut(const TestBlock& b, const TestCutter& t, const TestCutOptions& o) {
  check_testcut(b, t, o);
  TestCutPlan p;
  p.block = b;
  p.tool = t;
  p.tool_number = o.tool_number;
  p.spindle_rpm = o.spindle_rpm;
  p.fz_mm = o.fz_mm;
  p.feed_mm_per_min = on_grid(o.fz_mm * t.flutes * o.spindle_rpm);
  p.clearance_mm = o.clearance_mm;
  // Back face: segments from the corner X0/Y1 (kept free of the left face's
  // cuts, which reach x = X0 + a_e) towards X1; left face: from Y0 towards
  // the same corner.
  const double R = t.diameter_mm / 2, ae_max = largest(radial_depths(t, o));
  add_face(p, b, t, o, 0, on_grid(b.x0_mm + ae_max + o.gap_mm + R));
  add_face(p, b, t, o, 1, on_grid(b.y0_mm + o.gap_mm + R));
  return p;
}

void write_testcut(std::ostream& out, TestCutPlan& p, const profile::Dialect& d, const std::vector<std::string>& header) {
  auto num = [&](double v) { return writer::format_number(v, false, d); };
  std::vector<std::string> lines{"%"};
  for (const std::string& c : header) lines.push_back(writer::format_comment(c, d));
  const std::string t = std::to_string(p.tool_number);
  const double clear = p.block.z1_mm + p.clearance_mm;
  const Vec3& first = p.features.front().path.front();
  lines.push_back("G21 G90 G17 G40 G49 G80");
  lines.push_back("T" + t + " M6");
  lines.push_back("G54 G0 X" + num(first[0]) + " Y" + num(first[1]) + " S" +
                  std::to_string(std::lround(p.spindle_rpm)) + " M3");
  lines.push_back("G43 H" + t + " Z" + num(clear));
  for (std::size_t k = 0; k < p.features.size(); ++k) {
    WallFeature& f = p.features[k];
    const char* axis = f.feed_axis == 0 ? "X" : "Y";
    lines.push_back(writer::format_comment(f.id + ": WALL FED +" + axis + ", AE " + fixed_decimals(f.ae_mm, 3) + " AP " +
                                               fixed_decimals(f.ap_mm, 3) + " FZ " + fixed_decimals(f.fz_mm, 3) +
                                               " DOWN MILLING" + (f.morelli.empty() ? "" : ", MORELLI " + f.morelli),
                                           d));
    const std::vector<Vec3>& q = f.path;
    if (k) lines.push_back("G0 X" + num(q[0][0]) + " Y" + num(q[0][1]));
    lines.push_back("G1 Z" + num(q[1][2]) + " F" + num(p.feed_mm_per_min));  // down in air beside the block
    f.first_line = static_cast<int>(lines.size());
    const int in = f.feed_axis == 0 ? 1 : 0, along = f.feed_axis;
    const char in_letter = "XY"[in], along_letter = "XY"[along];
    lines.push_back(std::string(1, in_letter) + num(q[2][in]));        // in to the radial depth
    lines.push_back(std::string(1, along_letter) + num(q[3][along]));  // along the face
    lines.push_back(std::string(1, in_letter) + num(q[4][in]));        // out into air
    f.last_line = static_cast<int>(lines.size());
    lines.push_back("Z" + num(clear));  // up in air, fed: rapids only above the clearance
  }
  lines.insert(lines.end(), {"M5", "M30", "%"});
  for (const std::string& l : lines) out << l << "\n";
}

}  // namespace deflex::plan

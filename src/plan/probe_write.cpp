// The probing program written for a dialect (plan/probe.hpp): LinuxCNC's
// G38.2 with its probe log, or the ISO controls' G31 skip with DPRNT.
#include <ostream>

#include "deflex/diag/plural.hpp"
#include "deflex/plan/probe.hpp"
#include "deflex/writer/writer.hpp"

namespace deflex::plan {
namespace {

class ProbeWriter {
 public:
  ProbeWriter(std::ostream& out, const ProbeProgram& p, const profile::Dialect& d)
      : out_(out), p_(p), d_(d), linuxcnc_(d.name == "linuxcnc") {}

  void write(const std::vector<std::string>& header) {
    out_ << "%\n";
    for (const std::string& c : header) comment(c);
    out_ << "G21 G90 G17 G40 G49 G80 G94\n";
    const int t = p_.options.probe_tool;
    if (t > 0) out_ << "T" << t << " M6\nG54 G0 G43 H" << t << " Z" << num(p_.clear_z_mm) << "\n";
    else out_ << "G54 G0 Z" << num(p_.clear_z_mm) << "\n";
    comment("ACTIVATE THE PROBE HERE: ITS M CODE IS MACHINE-SPECIFIC (SEE THE PROBE INTERFACE MANUAL)");
    out_ << "M0\n";
    // LinuxCNC logs every G38.x trip point while the file is open; the ISO
    // controls print what DPRNT gives to the device POPEN opened.
    if (linuxcnc_) out_ << "(PROBEOPEN " << p_.options.results_file << ")\n";
    else out_ << "POPEN\n";
    for (std::size_t k = 0; k < p_.features.size(); ++k) feature(p_.plan.features[k], p_.features[k]);
    if (linuxcnc_) out_ << "(PROBECLOSE)\n";
    else out_ << "PCLOS\n";
    out_ << "M30\n%\n";
  }

 private:
  std::string num(double v) const { return writer::format_number(v, false, d_); }
  void comment(const std::string& c) { out_ << writer::format_comment(c, d_) << "\n"; }
  std::string xyz(const Vec3& v) const { return "X" + num(v[0]) + " Y" + num(v[1]) + " Z" + num(v[2]); }

  // Below the clearance plane: feeds and probing moves only.
  void feature(const WallFeature& f, const std::vector<ProbePoint>& pts) {
    const double r = p_.options.ball_diameter_mm / 2;
    const std::string move_f = " F" + num(p_.options.move_feed_mm_per_min);
    comment(f.id + ": " + plural(pts.size(), "POINT", "POINTS") + " ON THE WALL, AE " + fixed_decimals(f.ae_mm, 3) + " AP " +
            fixed_decimals(f.ap_mm, 3));
    const Vec3& s0 = pts.front().start_mm;
    out_ << "G0 X" << num(s0[0]) << " Y" << num(s0[1]) << "\n";
    out_ << "G1 Z" << num(s0[2]) << move_f << "\n";  // down in the air the cut left
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const ProbePoint& pt = pts[i];
      if (i) out_ << "G1 " << xyz(pt.start_mm) << move_f << "\n";  // along the wall at the approach distance
      // Byte-exact in every dialect: another reader parses it.
      out_ << "(" << probe_comment(pt, r) << ")\n";
      out_ << (linuxcnc_ ? "G38.2 " : "G31 ") << xyz(pt.end_mm) << " F" << num(p_.options.probe_feed_mm_per_min) << "\n";
      if (!linuxcnc_) out_ << "DPRNT[PT" << pt.id << "*X#5061[44]*Y#5062[44]*Z#5063[44]]\n";
      out_ << "G1 " << xyz(pt.start_mm) << move_f << "\n";  // back off along the normal
    }
    out_ << "G1 Z" << num(p_.clear_z_mm) << move_f << "\n";
  }

  std::ostream& out_;
  const ProbeProgram& p_;
  const profile::Dialect& d_;
  bool linuxcnc_;
};

}  // namespace

void write_probe(std::ostream& out, const ProbeProgram& p, const profile::Dialect& d, const std::vector<std::string>& header) {
  ProbeWriter(out, p, d).write(header);
}

}  // namespace deflex::plan

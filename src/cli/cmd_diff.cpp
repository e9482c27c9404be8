// deflex diff A B: pairs the blocks of two programs and tells whether they
// differ only in the coordinates of motion blocks, and by how much.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/report/json.hpp"
#include "deflex/compensate/pairing.hpp"
#include "deflex/gcode/skeleton.hpp"

namespace deflex::cli {
namespace {

struct Side {
  gcode::Program prog;
  std::vector<compensate::LineFacts> lines;  // index = line number
};

// The program and what pairing needs of each line; F words are left out of
// the skeletons so that a block whose feed changed still pairs (and is listed
// as changed in more than coordinates).
Side read_side(const std::string& file, const Setup& s, Diagnostics& diags, Io& io) {
  Side side{gcode::Program(gcode::read_source(file, &io.in)), {}};
  side.lines.resize(side.prog.line_count() + 1);
  compensate::LineFactsSink sink;
  sink.lines = &side.lines;
  interp::interpret(side.prog, s.interp(), diags, sink);
  compensate::fill_line_text(side.prog, side.lines, true);
  return side;
}

struct Change { std::uint32_t la, lb; double d[3]; double dist; bool edited; };
struct Split { std::uint32_t lb, la; double d; };
struct Report {
  std::vector<Change> changes;
  std::vector<Split> split_list;
  std::vector<std::string> other;
  double max_mm = 0, sum_mm = 0;
  std::size_t edited = 0;
};

// The JSON form: both files, the counts, every change of at least `threshold` mm.
report::Json diff_json(const Report& rep, const std::vector<std::string>& files, double threshold, double mean_mm) {
  report::Json changes = report::Json::array();
  for (const Change& c : rep.changes)
    if (c.dist >= threshold)
      changes.push_back({{"line_a", c.la}, {"line_b", c.lb}, {"d_mm", report::xyz(c.d[0], c.d[1], c.d[2], 6)},
                         {"distance_mm", report::fixed(c.dist, 6)}});
  return {{"file_a", files[0]}, {"file_b", files[1]}, {"blocks_changed", rep.changes.size()},
          {"blocks_edited", rep.edited}, {"blocks_inserted_splitting_moves", rep.split_list.size()},
          {"max_displacement_mm", report::fixed(rep.max_mm, 6)}, {"mean_displacement_mm", report::fixed(mean_mm, 6)},
          {"other_changes", rep.other.size()}, {"changes", changes}, {"other", rep.other}};
}

// Lines between two paired ones: a block only in B that splits the next
// paired move (deflex compensate inserts them) is a coordinate change, its
// displacement its distance from that move; everything else is listed.
void note_unpaired(const Side& a, const Side& b, const compensate::LinePairing& pairing,
                   const std::vector<std::string>& files, std::uint32_t from_a, std::uint32_t to_a,
                   std::uint32_t from_b, std::uint32_t to_b, Report& rep) {
  for (std::uint32_t l = from_a; l < to_a; ++l)
    rep.other.push_back(files[0] + ":" + std::to_string(l) + ": only in A: " + std::string(a.prog.source().line_text(l)));
  for (std::uint32_t l = from_b; l < to_b; ++l) {
    if (const std::uint32_t parent = pairing.parent_of_b[l]) {
      const compensate::V3 p(b.lines[l].path.end_mm[0], b.lines[l].path.end_mm[1], b.lines[l].path.end_mm[2]);
      const double d = (p - compensate::nearest_on(a.lines[parent].path, b.lines[l].path.end_mm)).norm();
      rep.split_list.push_back({l, parent, d});
      rep.max_mm = std::max(rep.max_mm, d);
      continue;
    }
    rep.other.push_back(files[1] + ":" + std::to_string(l) + ": only in B: " + std::string(b.prog.source().line_text(l)));
  }
}

// Whether two paired lines differ in their F words (skeletons with F).
bool feed_differs(const Side& a, const Side& b, std::uint32_t la, std::uint32_t lb) {
  Diagnostics quiet(nullptr, 0);
  gcode::Block x, y;
  a.prog.lex(la, x, quiet);
  b.prog.lex(lb, y, quiet);
  return gcode::skeleton_hash(a.prog, x) != gcode::skeleton_hash(b.prog, y);
}

// One paired line: unchanged, moved, or changed in more than coordinates.
void compare_pair(const Side& a, const Side& b, const std::vector<std::string>& files, std::uint32_t la,
                  std::uint32_t lb, Report& rep) {
  const compensate::LineFacts &x = a.lines[la], &y = b.lines[lb];
  std::string_view ta = a.prog.source().line_text(la), tb = b.prog.source().line_text(lb);
  // Same text but a different end point: an earlier change carried over by a
  // modal axis word. It moved, so it is listed, but it was not edited.
  if (ta == tb && x.motions == y.motions && (!x.motions || x.path.end_mm == y.path.end_mm)) return;
  if (x.motions != y.motions || x.path.kind != y.path.kind || (!x.motions && ta != tb) || feed_differs(a, b, la, lb)) {
    rep.other.push_back(files[0] + ":" + std::to_string(la) + " / " + files[1] + ":" + std::to_string(lb) +
                        ": changed in more than coordinates: '" + std::string(ta) + "' -> '" + std::string(tb) + "'");
    return;
  }
  const interp::Vec3 &e0 = x.path.end_mm, &e1 = y.path.end_mm;
  Change c{la, lb, {e1[0] - e0[0], e1[1] - e0[1], e1[2] - e0[2]}, 0, ta != tb};
  rep.edited += c.edited;
  c.dist = std::sqrt(c.d[0] * c.d[0] + c.d[1] * c.d[1] + c.d[2] * c.d[2]);
  rep.max_mm = std::max(rep.max_mm, c.dist);
  rep.sum_mm += c.dist;
  rep.changes.push_back(c);
}

Report compare(const Side& a, const Side& b, const compensate::LinePairing& pairing,
               const std::vector<std::string>& files) {
  Report rep;
  std::uint32_t pa = 0, pb = 0;  // last paired lines
  for (std::uint32_t lb = 1; lb < b.lines.size(); ++lb) {
    const std::uint32_t la = pairing.a_of_b[lb];
    if (!la) continue;
    note_unpaired(a, b, pairing, files, pa + 1, la, pb + 1, lb, rep);
    compare_pair(a, b, files, la, lb, rep);
    pa = la;
    pb = lb;
  }
  note_unpaired(a, b, pairing, files, pa + 1, static_cast<std::uint32_t>(a.lines.size()), pb + 1,
                static_cast<std::uint32_t>(b.lines.size()), rep);
  return rep;
}

}  // namespace

int cmd_diff(const std::vector<std::string>& args, Io& io) {
  ReadOptions r;
  std::vector<std::string> files;
  std::string format = "text";
  double threshold = 0.0, pair_mm = 1.0;
  bool help = false;
  po::options_description desc("options");
  desc.add_options()("help,h", po::bool_switch(&help), "show this help")
    ("format", po::value(&format)->default_value("text"), "text or json")
    ("min-mm", po::value(&threshold)->default_value(0.0), "list changed blocks that moved at least this far (mm); all are counted")
    ("pair-mm", po::value(&pair_mm)->default_value(1.0), "a block only in B within this of the next paired move counts as a split of it; of two blocks alike but for coordinates, the nearer pairs (mm)");
  add_read_options(desc, r);
  parse_with_files(args, desc, files, 2);
  if (help) {
    print_help(io.out, "deflex diff A B [--format text|json] [--dialect D]",
               "Pairs the blocks of program A (the original) with those of B (e.g. the compensated\n"
               "program) by structure: blocks that are the same but for their coordinate words\n"
               "(X Y Z I J K R) are paired in order, and their motion end points compared in 3D\n"
               "(mm, work frame); a G1 block only in B that lies on the move after it is a split\n"
               "of that move (what deflex compensate inserts). Every\n"
               "other difference - a G/M/F/S/T word, a comment, an inserted or deleted block, a\n"
               "different kind of motion - is listed as a change in more than coordinates.\n"
               "Exit 0 when only coordinates of motion blocks differ, 1 otherwise.\n", desc);
    return 0;
  }
  if (files.size() != 2) throw Error(ErrorKind::settings, "diff: two programs A and B are required");
  if (format != "text" && format != "json") throw Error(ErrorKind::settings, "--format takes text or json");
  Setup s = resolve(r);
  Diagnostics diags(&io.err, s.max_errors);
  Side a = read_side(files[0], s, diags, io);
  Side b = read_side(files[1], s, diags, io);
  if (diags.errors()) {
    io.err << "deflex: error: the programs have errors; no comparison made\n";
    return static_cast<int>(Exit::input);
  }
  if (!(pair_mm > 0)) throw Error(ErrorKind::settings, "--pair-mm must be > 0");
  const compensate::LinePairing pairing = compensate::pair_lines(a.lines, b.lines, {pair_mm});
  Report rep = compare(a, b, pairing, files);
  const std::vector<Change>& changes = rep.changes;
  const std::vector<std::string>& other = rep.other;
  const double max_mm = rep.max_mm, sum_mm = rep.sum_mm;
  const std::size_t edited = rep.edited, splits = rep.split_list.size();
  const auto& split_list = rep.split_list;
  double mean_mm = changes.empty() ? 0.0 : sum_mm / static_cast<double>(changes.size());
  char buf[256];
  if (format == "json") {
    io.out << report::line(diff_json(rep, files, threshold, mean_mm));
  } else {
    for (const Change& c : changes) {
      if (c.dist < threshold) continue;
      std::snprintf(buf, sizeof buf, "%u -> %u: dX %+.6f dY %+.6f dZ %+.6f |d| %.6f mm%s\n", c.la, c.lb, c.d[0], c.d[1],
                    c.d[2], c.dist, c.edited ? "" : " (not edited: carried over by a modal axis)");
      io.out << buf;
    }
    for (auto& [lb, la, d] : split_list) {
      std::snprintf(buf, sizeof buf, "+%u: inserted, splits the move of line %u; %.6f mm off it\n", lb, la, d);
      io.out << buf;
    }
    for (const std::string& o : other) io.out << o << "\n";
    std::snprintf(buf, sizeof buf, "%s moved (%zu edited), %s inserted splitting moves: max %.6f mm, mean %.6f mm; "
                  "%s in more than coordinates\n", plural(changes.size(), "motion block").c_str(), edited,
                  plural(splits, "block").c_str(), max_mm, mean_mm, plural(other.size(), "change").c_str());
    io.out << buf;
  }
  return other.empty() ? 0 : static_cast<int>(Exit::input);
}

}  // namespace deflex::cli

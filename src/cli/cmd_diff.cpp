// deflex diff A B: pairs the blocks of two programs (job::diff) and tells
// whether they differ only in the coordinates of motion blocks, and by how much.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "common.hpp"
#include "deflex/diag/plural.hpp"
#include "deflex/report/json.hpp"
#include "deflex/job/diff.hpp"

namespace deflex::cli {
namespace {

// The JSON form: both files, the counts, every change of at least `threshold` mm.
report::Json diff_json(const job::DiffResult& rep, const std::vector<std::string>& files, double threshold) {
  report::Json changes = report::Json::array();
  for (const job::DiffChange& c : rep.changes)
    if (c.distance_mm >= threshold)
      changes.push_back({{"line_a", c.line_a}, {"line_b", c.line_b},
                         {"d_mm", report::xyz(c.d_mm[0], c.d_mm[1], c.d_mm[2], 6)},
                         {"distance_mm", report::fixed(c.distance_mm, 6)}});
  return {{"file_a", files[0]}, {"file_b", files[1]}, {"blocks_changed", rep.changes.size()},
          {"blocks_edited", rep.edited}, {"blocks_inserted_splitting_moves", rep.splits.size()},
          {"max_displacement_mm", report::fixed(rep.max_mm, 6)}, {"mean_displacement_mm", report::fixed(rep.mean_mm, 6)},
          {"other_changes", rep.other.size()}, {"changes", changes}, {"other", rep.other}};
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
  job::DiffSettings ds;
  ds.a = files[0];
  ds.b = files[1];
  ds.read = r;
  ds.pair_mm = pair_mm;
  const job::DiffResult rep = job::diff(ds, io);
  char buf[256];
  if (format == "json") {
    io.out << report::line(diff_json(rep, files, threshold));
  } else {
    for (const job::DiffChange& c : rep.changes) {
      if (c.distance_mm < threshold) continue;
      std::snprintf(buf, sizeof buf, "%u -> %u: dX %+.6f dY %+.6f dZ %+.6f |d| %.6f mm%s\n", c.line_a, c.line_b,
                    c.d_mm[0], c.d_mm[1], c.d_mm[2], c.distance_mm,
                    c.edited ? "" : " (not edited: carried over by a modal axis)");
      io.out << buf;
    }
    for (const job::DiffSplit& sp : rep.splits) {
      std::snprintf(buf, sizeof buf, "+%u: inserted, splits the move of line %u; %.6f mm off it\n", sp.line_b,
                    sp.line_a, sp.distance_mm);
      io.out << buf;
    }
    for (const std::string& o : rep.other) io.out << o << "\n";
    std::snprintf(buf, sizeof buf, "%s moved (%zu edited), %s inserted splitting moves: max %.6f mm, mean %.6f mm; "
                  "%s in more than coordinates\n", plural(rep.changes.size(), "motion block").c_str(), rep.edited,
                  plural(rep.splits.size(), "block").c_str(), rep.max_mm, rep.mean_mm,
                  plural(rep.other.size(), "change").c_str());
    io.out << buf;
  }
  return rep.only_coordinates() ? 0 : static_cast<int>(Exit::input);
}

}  // namespace deflex::cli

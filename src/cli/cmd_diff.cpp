// deflex diff A B: pairs the blocks of two programs and tells whether they
// differ only in the coordinates of motion blocks, and by how much.
#include <algorithm>
#include <cmath>
#include <tuple>
#include <cstdio>
#include <iostream>

#include "common.hpp"
#include "deflex/gcode/skeleton.hpp"

namespace deflex::cli {
namespace {

// Per source line: a hash of the block with its coordinate words taken out
// (its "skeleton"), and where its last motion ends.
struct LineInfo {
  std::uint64_t skeleton = 0;
  interp::Vec3 start{};  // where the line's first motion starts
  interp::Vec3 end{};
  interp::Vec3 center{};  // of the last motion, when an arc
  std::uint32_t motions = 0;
  std::uint8_t kind = 0;  // MotionKind of the last motion
  std::uint8_t plane = 17;
};

struct Collector : interp::MotionSink {
  std::vector<LineInfo>* lines;
  void motion(const interp::Motion& m) override {
    LineInfo& li = (*lines)[m.line];
    if (!li.motions) li.start = m.start_mm;
    li.end = m.end_mm;
    li.kind = static_cast<std::uint8_t>(m.kind);
    li.center = m.center_mm;
    li.plane = m.plane;
    ++li.motions;
  }
};

struct Side {
  gcode::Program prog;
  std::vector<LineInfo> lines;  // index = line number
  bool ok = true;
};

Side read_side(const std::string& file, const Setup& s, Diagnostics& diags, Io& io) {
  Side side{gcode::Program(gcode::read_source(file, &io.in)), {}, true};
  const gcode::Program& p = side.prog;
  side.lines.resize(p.line_count() + 1);
  Collector c;
  c.lines = &side.lines;
  interp::Stats st = interp::interpret(p, s.interp(), diags, c);
  side.ok = !st.stopped;
  // Skeleton: the block without its coordinate words (gcode/skeleton.hpp).
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  for (std::uint32_t l = 1; l <= p.line_count(); ++l) {
    p.lex(l, b, quiet);
    side.lines[l].skeleton = gcode::skeleton_hash(p, b);
  }
  return side;
}

// Myers' O(ND) shortest edit script over skeleton hashes; returns pairs of
// matched lines (1-based). Gives up (empty, false) past max_d edits.
// Two lines match when their skeletons do and, for motion blocks, their end
// points lie within pair_mm: in a program of `G1X..Y..` lines every skeleton is
// the same, and only the position tells an inserted block from its neighbours.
bool same_line(const LineInfo& x, const LineInfo& y, double pair_mm) {
  if (x.skeleton != y.skeleton) return false;
  if (!x.motions || !y.motions) return x.motions == y.motions;
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (x.end[k] - y.end[k]) * (x.end[k] - y.end[k]);
  return d2 <= pair_mm * pair_mm;
}

bool align(const std::vector<LineInfo>& a, const std::vector<LineInfo>& b,
           std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, int max_d, double pair_mm) {
  const int n = static_cast<int>(a.size()) - 1, m = static_cast<int>(b.size()) - 1;
  const int off = max_d + 1;
  std::vector<int> v(2 * off + 2, 0);
  std::vector<std::vector<int>> trace;
  auto eq = [&](int x, int y) { return same_line(a[x + 1], b[y + 1], pair_mm); };
  for (int d = 0; d <= max_d; ++d) {
    trace.push_back(v);
    for (int k = -d; k <= d; k += 2) {
      int x = (k == -d || (k != d && v[off + k - 1] < v[off + k + 1])) ? v[off + k + 1] : v[off + k - 1] + 1;
      int y = x - k;
      while (x < n && y < m && eq(x, y)) { ++x; ++y; }
      v[off + k] = x;
      if (x >= n && y >= m) {
        // Walk back through the trace to recover the matches.
        std::vector<std::pair<std::uint32_t, std::uint32_t>> rev;
        for (int dd = d; dd > 0; --dd) {
          const std::vector<int>& vp = trace[dd];
          int kk = x - y;
          int pk = (kk == -dd || (kk != dd && vp[off + kk - 1] < vp[off + kk + 1])) ? kk + 1 : kk - 1;
          int px = vp[off + pk], py = px - pk;
          while (x > px && y > py && x > 0 && y > 0 && eq(x - 1, y - 1)) { rev.push_back({x, y}); --x; --y; }
          x = px;
          y = py;
        }
        while (x > 0 && y > 0) { rev.push_back({x, y}); --x; --y; }
        pairs.assign(rev.rbegin(), rev.rend());
        return true;
      }
    }
  }
  return false;
}

std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') { o += '\\'; o += c; }
    else if (static_cast<unsigned char>(c) < 0x20) { char b[8]; std::snprintf(b, sizeof b, "\\u%04x", c); o += b; }
    else o += c;
  }
  return o + "\"";
}

// A single line only in B (a block deflex inserted) can be placed anywhere in
// the run of pairs before it at the same edit distance; the greedy alignment
// puts it last. Slide it to where the paired end points move least in total.
void slide_insertions(std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs, const std::vector<LineInfo>& a,
                      const std::vector<LineInfo>& b) {
  auto dist = [&](std::uint32_t la, std::uint32_t lb) {
    if (!a[la].motions || !b[lb].motions) return 0.0;
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (a[la].end[k] - b[lb].end[k]) * (a[la].end[k] - b[lb].end[k]);
    return std::sqrt(d2);
  };
  auto alike = [&](std::uint32_t la, std::uint32_t lb) {
    return lb < b.size() && a[la].skeleton == b[lb].skeleton && a[la].motions == b[lb].motions;
  };
  // A sentinel one past the last lines lets a trailing insertion slide too.
  pairs.push_back({static_cast<std::uint32_t>(a.size()), static_cast<std::uint32_t>(b.size())});
  for (std::size_t k = 1; k < pairs.size(); ++k) {
    const auto [a1, b1] = pairs[k];
    const auto [a0, b0] = pairs[k - 1];
    if (a1 != a0 + 1 || b1 != b0 + 2) continue;  // not a single B-only line between them
    // The run of consecutive pairs ending at k - 1 (at most 64 back).
    std::size_t j0 = k - 1;
    while (j0 > 0 && k - j0 < 64 && pairs[j0 - 1].first + 1 == pairs[j0].first &&
           pairs[j0 - 1].second + 1 == pairs[j0].second)
      --j0;
    // Gap before pair j: pairs j..k-1 shift to the next B line.
    double keep = 0, best = 0;
    for (std::size_t i = j0; i < k; ++i) keep += dist(pairs[i].first, pairs[i].second);
    best = keep;
    std::size_t best_j = k;
    double before = 0, shifted = 0;
    std::vector<double> shift_cost(k - j0 + 1, 0.0);
    bool ok = true;
    for (std::size_t i = k; i-- > j0;) {
      if (!alike(pairs[i].first, pairs[i].second + 1)) { ok = false; }
      shifted += dist(pairs[i].first, pairs[i].second + 1);
      shift_cost[i - j0] = ok ? shifted : -1;
    }
    for (std::size_t j = j0; j < k; ++j) {
      if (shift_cost[j - j0] >= 0 && before + shift_cost[j - j0] < best - 1e-12) {
        best = before + shift_cost[j - j0];
        best_j = j;
      }
      before += dist(pairs[j].first, pairs[j].second);
    }
    for (std::size_t i = best_j; i < k; ++i) ++pairs[i].second;
  }
  pairs.pop_back();
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
    ("pair-mm", po::value(&pair_mm)->default_value(1.0), "blocks alike but for coordinates pair first when their end points are this close (mm)");
  add_read_options(desc, r);
  parse_with_files(args, desc, files, 2);
  if (help) {
    print_help(io.out, "deflex diff A B [--format text|json] [--dialect D]",
               "Pairs the blocks of program A (the original) with those of B (e.g. the compensated\n"
               "program): blocks that are the same but for their coordinate words (X Y Z I J K R)\n"
               "are paired, and their motion end points compared in 3D (mm, work frame). Every\n"
               "other difference - a G/M/F/S/T word, a comment, an inserted or deleted block, a\n"
               "different kind of motion - is listed as a change in more than coordinates.\n"
               "Exit 0 when only coordinates of motion blocks differ, 1 otherwise.\n", desc);
    return 0;
  }
  if (files.size() != 2) throw Error(Exit::usage, "diff: two programs A and B are required");
  if (format != "text" && format != "json") throw Error(Exit::usage, "--format takes text or json");
  Setup s = resolve(r);
  Diagnostics diags(&io.err, s.max_errors);
  Side a = read_side(files[0], s, diags, io);
  Side b = read_side(files[1], s, diags, io);
  if (diags.errors()) {
    io.err << "deflex: error: the programs have errors; no comparison made\n";
    return static_cast<int>(Exit::input);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  int max_d = 20000;
  if (!(pair_mm > 0)) throw Error(Exit::usage, "--pair-mm must be > 0");
  if (!align(a.lines, b.lines, pairs, max_d, pair_mm))
    throw Error(Exit::input, "diff: the programs differ in more than " + std::to_string(max_d) + " blocks; not compared");
  {
    // Blocks moved further than pair_mm leave equal-length runs unpaired on
    // both sides: pair them back when their skeletons match one to one.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> all;
    std::uint32_t qa = 0, qb = 0;
    auto gap = [&](std::uint32_t ea, std::uint32_t eb) {
      const std::uint32_t na = ea - qa - 1, nb = eb - qb - 1;
      if (na == 0 || na != nb) return;
      for (std::uint32_t k = 1; k <= na; ++k)
        if (a.lines[qa + k].skeleton != b.lines[qb + k].skeleton || a.lines[qa + k].motions != b.lines[qb + k].motions) return;
      for (std::uint32_t k = 1; k <= na; ++k) all.push_back({qa + k, qb + k});
    };
    for (auto [la, lb] : pairs) {
      gap(la, lb);
      all.push_back({la, lb});
      qa = la;
      qb = lb;
    }
    gap(static_cast<std::uint32_t>(a.lines.size()), static_cast<std::uint32_t>(b.lines.size()));
    pairs = std::move(all);
  }
  slide_insertions(pairs, a.lines, b.lines);

  struct Change { std::uint32_t la, lb; double d[3]; double dist; bool edited; };
  std::vector<Change> changes;
  std::vector<std::string> other;
  double max_mm = 0, sum_mm = 0;
  std::size_t edited = 0;
  std::uint32_t pa = 0, pb = 0;  // last paired lines
  // A block only in B that splits the next paired move (deflex compensate
  // inserts them: N, G1, X, Y, Z, F only, its point on that move within 1 mm)
  // is a coordinate change: its displacement is its distance from the move.
  std::size_t splits = 0;
  Diagnostics quiet(nullptr, 0);
  gcode::Block blk;
  auto split_distance = [&](std::uint32_t lb, std::uint32_t next_la) -> double {
    if (!next_la || next_la >= a.lines.size() || !b.lines[lb].motions || b.lines[lb].kind != 1 ||
        a.lines[next_la].kind == 0 || a.lines[next_la].motions != 1)
      return -1;
    b.prog.lex(lb, blk, quiet);
    for (const gcode::Word& w : blk.words)
      if (!(w.letter == 'N' || w.letter == 'X' || w.letter == 'Y' || w.letter == 'Z' || w.letter == 'F' ||
            (w.letter == 'G' && w.code10() == 10)))
        return -1;
    if (!blk.comments.empty()) return -1;
    const interp::Vec3 &s0 = a.lines[next_la].start, &s1 = a.lines[next_la].end, &p = b.lines[lb].end;
    if (a.lines[next_la].kind != 1) {
      // A chord end of a linearised arc: its distance from the arc's circle
      // (in the plane) and plane (along the axis).
      const interp::Vec3& c = a.lines[next_la].center;
      const int normal = a.lines[next_la].plane == 17 ? 2 : a.lines[next_la].plane == 18 ? 1 : 0;
      double r2 = 0, p2 = 0;
      for (int k = 0; k < 3; ++k) {
        if (k == normal) continue;
        r2 += (s0[k] - c[k]) * (s0[k] - c[k]);
        p2 += (p[k] - c[k]) * (p[k] - c[k]);
      }
      const double radial = std::sqrt(p2) - std::sqrt(r2), axial = p[normal] - s0[normal];
      const double d = std::sqrt(radial * radial + axial * axial);
      return d <= 1.0 ? d : -1;
    }
    double ab[3], ap[3], ab2 = 0, t = 0, d2 = 0;
    for (int k = 0; k < 3; ++k) { ab[k] = s1[k] - s0[k]; ap[k] = p[k] - s0[k]; ab2 += ab[k] * ab[k]; t += ap[k] * ab[k]; }
    t = ab2 > 0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
    for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
    const double d = std::sqrt(d2);
    return d <= 1.0 ? d : -1;
  };
  std::vector<std::tuple<std::uint32_t, std::uint32_t, double>> split_list;
  auto note_unpaired = [&](std::uint32_t from_a, std::uint32_t to_a, std::uint32_t from_b, std::uint32_t to_b,
                           std::uint32_t next_la) {
    for (std::uint32_t l = from_a; l < to_a; ++l)
      other.push_back(files[0] + ":" + std::to_string(l) + ": only in A: " + std::string(a.prog.source().line_text(l)));
    for (std::uint32_t l = from_b; l < to_b; ++l) {
      if (from_a == to_a) {
        const double d = split_distance(l, next_la);
        if (d >= 0) {
          ++splits;
          split_list.emplace_back(l, next_la, d);
          max_mm = std::max(max_mm, d);
          continue;
        }
      }
      other.push_back(files[1] + ":" + std::to_string(l) + ": only in B: " + std::string(b.prog.source().line_text(l)));
    }
  };
  for (auto [la, lb] : pairs) {
    note_unpaired(pa + 1, la, pb + 1, lb, la);
    pa = la;
    pb = lb;
    const LineInfo &x = a.lines[la], &y = b.lines[lb];
    std::string_view ta = a.prog.source().line_text(la), tb = b.prog.source().line_text(lb);
    // Same text but a different end point: an earlier change carried over by a
    // modal axis word. It moved, so it is listed, but it was not edited.
    if (ta == tb && x.motions == y.motions && (!x.motions || x.end == y.end)) continue;
    if (x.motions != y.motions || x.kind != y.kind || (!x.motions && ta != tb)) {
      other.push_back(files[0] + ":" + std::to_string(la) + " / " + files[1] + ":" + std::to_string(lb) +
                      ": changed in more than coordinates: '" + std::string(ta) + "' -> '" + std::string(tb) + "'");
      continue;
    }
    Change c{la, lb, {y.end[0] - x.end[0], y.end[1] - x.end[1], y.end[2] - x.end[2]}, 0, ta != tb};
    edited += c.edited;
    c.dist = std::sqrt(c.d[0] * c.d[0] + c.d[1] * c.d[1] + c.d[2] * c.d[2]);
    max_mm = std::max(max_mm, c.dist);
    sum_mm += c.dist;
    changes.push_back(c);
  }
  note_unpaired(pa + 1, static_cast<std::uint32_t>(a.lines.size()), pb + 1, static_cast<std::uint32_t>(b.lines.size()), 0);
  double mean_mm = changes.empty() ? 0.0 : sum_mm / static_cast<double>(changes.size());
  char buf[256];
  if (format == "json") {
    io.out << "{\"a\": \"" << files[0] << "\", \"b\": \"" << files[1] << "\", \"blocks_changed\": " << changes.size()
           << ", \"blocks_edited\": " << edited << ", \"blocks_inserted_splitting_moves\": " << splits;
    std::snprintf(buf, sizeof buf, ", \"max_displacement_mm\": %.6f, \"mean_displacement_mm\": %.6f", max_mm, mean_mm);
    io.out << buf << ", \"other_changes\": " << other.size() << ", \"changes\": [";
    bool first = true;
    for (const Change& c : changes) {
      if (c.dist < threshold) continue;
      std::snprintf(buf, sizeof buf, "%s{\"line_a\": %u, \"line_b\": %u, \"d_mm\": [%.6f, %.6f, %.6f], \"distance_mm\": %.6f}",
                    first ? "" : ", ", c.la, c.lb, c.d[0], c.d[1], c.d[2], c.dist);
      io.out << buf;
      first = false;
    }
    io.out << "], \"other\": [";
    for (std::size_t i = 0; i < other.size(); ++i) io.out << (i ? ", " : "") << json_string(other[i]);
    io.out << "]}\n";
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
    std::snprintf(buf, sizeof buf,
                  "%zu motion blocks moved (%zu edited), %zu blocks inserted splitting moves: max %.6f mm, mean %.6f mm; "
                  "%zu changes in more than coordinates\n",
                  changes.size(), edited, splits, max_mm, mean_mm, other.size());
    io.out << buf;
  }
  return other.empty() ? 0 : static_cast<int>(Exit::input);
}

}  // namespace deflex::cli

#include "deflex/writer/writer.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string_view>
#include <sys/stat.h>
#include <unistd.h>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/writer/temp_files.hpp"

namespace deflex::writer {
namespace fs = std::filesystem;

namespace {

bool coordinate_letter(char l) { return std::strchr("XYZIJKR", l) != nullptr; }

// Evidence of one letter's style, counted over the words of the lines read.
struct LetterCount {
  std::array<std::uint32_t, 10> decimals{};  // words with a point, by their number of decimals
  std::uint32_t with_point = 0, trailing_zero = 0, leading_zero = 0, bare_point = 0;
  void add(std::string_view written) {
    std::string num;  // the number without the blanks a word may hold (X 10 . 0)
    for (char c : written)
      if (c != ' ' && c != '\t') num += c;
    const std::size_t dot = num.find('.');
    if (dot == std::string_view::npos) return;
    ++with_point;
    const std::size_t k = num.size() - dot - 1;
    ++decimals[std::min<std::size_t>(k, 9)];
    if (k > 0 && num.back() == '0') ++trailing_zero;
    const std::string_view mag = std::string_view(num).substr(num.starts_with('-') || num.starts_with('+') ? 1 : 0);
    if (mag.starts_with("0.")) ++leading_zero;
    else if (mag.starts_with('.')) ++bare_point;
  }
  void merge(const LetterCount& o) {
    for (std::size_t k = 0; k < decimals.size(); ++k) decimals[k] += o.decimals[k];
    with_point += o.with_point;
    trailing_zero += o.trailing_zero;
    leading_zero += o.leading_zero;
    bare_point += o.bare_point;
  }
  // Fixed width: trailing zeros are written, and 95 % of the numbers have the
  // same decimals (a trimming post writes 12.5 and 12.125 side by side).
  int fixed() const {
    if (!trailing_zero) return NumberStyle::kUnknown;
    const auto mode = std::max_element(decimals.begin(), decimals.end());
    return *mode >= 0.95 * with_point ? static_cast<int>(mode - decimals.begin()) : NumberStyle::kUnknown;
  }
  int leading() const {
    if (leading_zero) return 1;
    return bare_point ? 0 : NumberStyle::kUnknown;
  }
};

}  // namespace

NumberStyle learn_style(const gcode::Program& p, std::uint32_t max_lines) {
  std::array<LetterCount, 26> count{};
  std::uint32_t multi_word = 0, with_blank = 0;
  Diagnostics quiet(nullptr, 0);
  gcode::Block b;
  const std::string& bytes = p.bytes();
  for (std::uint32_t l = p.first_line(); l <= p.last_line() && l < p.first_line() + max_lines; ++l) {
    if (!p.lex(l, b, quiet) || b.kind != gcode::LineKind::block || b.macro) continue;
    for (std::size_t k = 0; k < b.words.size(); ++k) {
      const gcode::Word& w = b.words[k];
      if (w.letter >= 'A' && w.letter <= 'Z')
        count[w.letter - 'A'].add(std::string_view(bytes).substr(w.num_begin, w.end - w.num_begin));
      if (k) with_blank += w.begin > b.words[k - 1].end;
    }
    multi_word += b.words.size() > 1;
  }
  NumberStyle s;
  s.blanks = !multi_word || with_blank > 0;
  LetterCount coords;
  for (char l : std::string_view("XYZIJKR")) coords.merge(count[l - 'A']);
  for (int k = 0; k < 26; ++k) {
    const LetterCount& own = count[k];
    // A post writes all its axes and centre words alike.
    const LetterCount& c = coordinate_letter(static_cast<char>('A' + k)) ? coords : own;
    s.fixed_decimals[k] = c.fixed();
    s.leading_zero[k] = c.leading();
  }
  return s;
}

namespace {

int written_decimals(bool inch, const profile::Dialect& d) {
  int decimals = inch ? d.decimals_inch : d.decimals_mm;
  // A control that counts least input increments refuses (Fanuc: "too many
  // digits") or drops digits finer than its increment: never write them.
  if (d.decimal_rule == profile::DecimalRule::least_input_increment) {
    const double lii = inch ? d.lii_inch : d.lii_mm;
    if (lii > 0) decimals = std::min(decimals, static_cast<int>(std::lround(-std::log10(lii))));
  }
  return decimals;
}

}  // namespace

double rounding_mm(bool inch, const profile::Dialect& d) {
  return 0.5 * std::pow(10.0, -written_decimals(inch, d)) * (inch ? 25.4 : 1.0);
}

std::string format_number(double value, bool inch, const profile::Dialect& d, const NumberStyle* style, char letter) {
  const int decimals = written_decimals(inch, d);
  const int k = letter >= 'A' && letter <= 'Z' ? letter - 'A' : -1;
  const int fixed = style && k >= 0 ? style->fixed_decimals[k] : NumberStyle::kUnknown;
  const int lead = style && k >= 0 ? style->leading_zero[k] : NumberStyle::kUnknown;
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
  std::string s(buf, r.ptr);
  if (decimals == 0) s += '.';
  if (fixed != NumberStyle::kUnknown || !d.trailing_zeros) {
    while (s.back() == '0') s.pop_back();  // "12.500" -> "12.5", "12.000" -> "12."
  }
  if (fixed != NumberStyle::kUnknown) {
    // Padded to the program's width with zeros only: the value read back is
    // the one rounded above.
    const std::size_t have = s.size() - s.find('.') - 1;
    if (have < static_cast<std::size_t>(fixed)) s.append(static_cast<std::size_t>(fixed) - have, '0');
  }
  if (s.starts_with('-') && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);  // no negative zero
  if (lead == 0 || (lead == NumberStyle::kUnknown && !d.leading_zero)) {
    if (s.starts_with("0.") && s.size() > 2) s.erase(0, 1);
    else if (s.starts_with("-0.")) s.erase(1, 1);
  }
  return s;
}

std::string format_comment(const std::string& text, const profile::Dialect& d) {
  if (d.comment_style == profile::CommentStyle::semicolon) return "; " + text;
  std::string t = text;
  for (char& c : t) {
    if (c == '(') c = '[';
    if (c == ')') c = ']';
  }
  return "(" + t + ")";
}

std::string Rewriter::format_block(std::uint32_t after_line, const std::vector<std::pair<char, double>>& words,
                                   bool inch, const std::string& comment, const std::string& lead) {
  std::string s;
  if (d_.n_policy != profile::NPolicy::none) {
    // The numbers of the nearest numbered blocks before and after the gap (at
    // most 200 lines away: N numbers are for the operator's eye, not exact).
    Diagnostics quiet(nullptr, 0);
    gcode::Block b;
    auto n_at = [&](std::uint32_t l) -> std::optional<long> {
      prog_.lex(l, b, quiet);
      const gcode::Word* w = b.find('N');
      if (!w || !(w->value >= 0 && w->value < 1e9)) return std::nullopt;
      return static_cast<long>(w->value);
    };
    long before = 0;
    std::optional<long> after;
    for (std::uint32_t l = after_line; l >= prog_.first_line() && l + 200 > after_line; --l)
      if (auto n = n_at(l)) { before = *n; break; }
    for (std::uint32_t l = after_line + 1; l <= prog_.last_line() && l < after_line + 200; ++l)
      if ((after = n_at(l))) break;
    long& taken = (*numbers_taken_)[before];
    const long n = before + 1 + taken;
    if (!after || n < *after) {
      s = "N" + std::to_string(n);
      ++taken;
    } else if (d_.n_policy == profile::NPolicy::required) {
      throw Error(ErrorKind::input, prog_.source().name() + ":" + std::to_string(after_line + 1) +
                                   ":1: error: no free N number between N" + std::to_string(before) + " and N" +
                                   std::to_string(*after) + " for a block deflex inserts here (dialect " + d_.name +
                                   " requires N on every block): renumber the program with a larger step");
    }
  }
  const std::string blank = style().blanks ? " " : "";
  if (!lead.empty()) s += (s.empty() ? "" : blank) + lead;
  for (auto& [letter, value] : words) {
    if (!s.empty()) s += blank;
    s += letter;
    s += number(letter, value, inch);
  }
  if (!comment.empty()) s += (s.empty() ? "" : " ") + format_comment(comment, d_);
  return s;
}

const NumberStyle& Rewriter::style() {
  if (!style_) style_ = learn_style(prog_);
  return *style_;
}

std::string Rewriter::number(char letter, double value, bool inch) {
  return format_number(value, inch, d_, &style(), letter);
}

void Rewriter::set_number(const gcode::Word& w, double value, bool inch) {
  edits_.push_back({w.num_begin, w.end, static_cast<std::uint32_t>(edits_.size()), number(w.letter, value, inch)});
}

void Rewriter::insert_word(std::uint32_t at, char letter, double value, bool inch) {
  edits_.push_back({at, at, static_cast<std::uint32_t>(edits_.size()),
                    (style().blanks ? " " : "") + std::string(1, letter) + number(letter, value, inch)});
}

void Rewriter::insert_block_after(std::uint32_t line, const std::string& text) {
  const SourceText& src = prog_.source();
  std::uint32_t at = src.line_end_with_eol(line);
  std::string_view whole(src.bytes());
  // The new line takes the line ending of the line it follows; if that line had
  // none (last line of the file), it gets one and the new line keeps none.
  std::uint32_t text_end = src.line_begin(line) + static_cast<std::uint32_t>(src.line_text(line).size());
  std::string eol(whole.substr(text_end, at - text_end));
  std::string ins = eol.empty() ? "\n" + text : text + eol;
  edits_.push_back({at, at, static_cast<std::uint32_t>(edits_.size()), ins, true});
}

void Rewriter::insert_block_before(std::uint32_t line, const std::string& text) {
  const SourceText& src = prog_.source();
  auto eol_of = [&](std::uint32_t l) {
    std::uint32_t end = src.line_end_with_eol(l);
    std::uint32_t text_end = src.line_begin(l) + static_cast<std::uint32_t>(src.line_text(l).size());
    return std::string(std::string_view(src.bytes()).substr(text_end, end - text_end));
  };
  std::string eol = eol_of(line);
  if (eol.empty() && line > prog_.first_line()) eol = eol_of(line - 1);
  if (eol.empty()) eol = "\n";
  std::uint32_t at = src.line_begin(line);
  edits_.push_back({at, at, static_cast<std::uint32_t>(edits_.size()), text + eol, true});
}

void Rewriter::write(std::ostream& out) {
  if (prog_.line_count() == 0) {
    out.write(prog_.bytes().data(), static_cast<std::streamsize>(prog_.bytes().size()));
    return;
  }
  write(out, prog_.first_line(), prog_.last_line());
}

void Rewriter::write(std::ostream& out, std::uint32_t first_line, std::uint32_t last_line) {
  std::stable_sort(edits_.begin(), edits_.end(), [](const Edit& a, const Edit& b) {
    return a.begin != b.begin ? a.begin < b.begin : a.seq < b.seq;
  });
  const SourceText& src = prog_.source();
  const std::string& s = prog_.bytes();
  std::uint32_t pos = src.line_begin(first_line);
  const std::uint32_t end = src.line_end_with_eol(last_line);
  for (const Edit& e : edits_) {
    if (e.begin < pos || e.end > end) throw Error(ErrorKind::internal, "writer: edits overlap or lie outside the lines written");
    out.write(s.data() + pos, e.begin - pos);
    out << e.text;
    pos = e.end;
  }
  out.write(s.data() + pos, static_cast<std::streamsize>(end - pos));
  if (d_.max_line_length > 0 && !edits_.empty()) check_line_lengths();
}

void Rewriter::check_line_lengths() const {
  // Only changed lines can newly break the limit. Edits are sorted, so one pass
  // sums the length change of each touched line; a new block is its own line.
  const SourceText& src = prog_.source();
  auto fail = [&](std::uint32_t line, long len, const char* what) {
    throw Error(ErrorKind::input, src.name() + ":" + std::to_string(line) + ":1: error: " + what + " is " +
                                 std::to_string(len) + " characters, over the " + d_.name + " limit of " +
                                 std::to_string(d_.max_line_length));
  };
  std::uint32_t cur = 0;
  long delta = 0;
  auto flush = [&] {
    long len = static_cast<long>(src.line_text(cur).size()) + delta;
    if (cur && len > d_.max_line_length) fail(cur, len, "rewritten block");
  };
  for (const Edit& e : edits_) {
    if (e.new_block) {
      long len = static_cast<long>(std::count_if(e.text.begin(), e.text.end(), [](char c) { return c != '\r' && c != '\n'; }));
      if (len > d_.max_line_length) fail(src.line_of(e.begin ? e.begin - 1 : 0), len, "inserted block after this line");
      continue;
    }
    std::uint32_t line = src.line_of(e.begin);
    if (line != cur) { flush(); cur = line; delta = 0; }
    delta += static_cast<long>(e.text.size()) - static_cast<long>(e.end - e.begin);
  }
  flush();
}

std::string Rewriter::str() {
  std::ostringstream ss;
  write(ss);
  return ss.str();
}

void check_output_path(const std::string& path, const std::string& input_path) {
  std::error_code ec;
  if (path.empty()) throw Error(ErrorKind::settings, "error: empty output path");
  const fs::file_status st = fs::status(path, ec);  // follows symlinks
  if (fs::exists(st)) {
    if (!input_path.empty() && input_path != "-" && fs::equivalent(path, input_path, ec))
      throw Error(ErrorKind::settings, path + ": error: output would overwrite the input program; choose another -o");
    if (!fs::is_regular_file(st))
      throw Error(ErrorKind::settings, path + ": error: not a regular file (a " +
                                   std::string(fs::is_directory(st) ? "directory" : "device, FIFO or socket") +
                                   "); deflex writes outputs only to regular files");
  } else if (fs::is_symlink(fs::symlink_status(path, ec))) {
    throw Error(ErrorKind::settings, path + ": error: a symbolic link to nothing; give the target itself");
  }
  const fs::path target = fs::exists(st) ? fs::canonical(path, ec) : fs::path(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw Error(ErrorKind::settings, path + ": error: the folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK) != 0)
    throw Error(ErrorKind::io, path + ": error: the folder " + dir.string() + " is not writable: " + std::strerror(errno));
}

void check_output_folder(const std::string& dir) {
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st)) throw Error(ErrorKind::settings, dir + ": error: exists and is not a folder");
    if (::access(dir.c_str(), W_OK) != 0) throw Error(ErrorKind::io, dir + ": error: the folder is not writable: " + std::strerror(errno));
    return;
  }
  const fs::path parent = fs::path(dir).lexically_normal().parent_path();
  const fs::path p = parent.empty() ? fs::path(".") : parent;
  if (!fs::is_directory(p, ec)) throw Error(ErrorKind::settings, dir + ": error: the folder " + p.string() + " does not exist");
  if (::access(p.c_str(), W_OK) != 0)
    throw Error(ErrorKind::io, dir + ": error: cannot create it: " + p.string() + " is not writable: " + std::strerror(errno));
}

AtomicFile::AtomicFile(const std::string& path, const std::string& input_path) : path_(path) {
  check_output_path(path, input_path);
  std::error_code ec;
  // Through a symlink the target is replaced, so the link stays a link.
  const bool existed = fs::exists(path, ec);
  target_ = existed ? fs::canonical(path, ec).string() : path;
  struct stat old {};
  have_old_ = existed && ::stat(target_.c_str(), &old) == 0;
  old_mode_ = old.st_mode;
  old_uid_ = old.st_uid;
  old_gid_ = old.st_gid;
  const fs::path target(target_);
  fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string hidden(".");
  hidden.append(target.filename().string()).append(".deflex-XXXXXX");
  tmp_ = (dir / hidden).string();
  const int fd = temp_files::create(tmp_, slot_);
  if (fd < 0) throw Error(ErrorKind::io, path + ": error: cannot create a temporary file in " + dir.string() + ": " + std::strerror(errno));
  ::close(fd);
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    std::remove(tmp_.c_str());
    temp_files::forget(slot_);
    throw Error(ErrorKind::io, path + ": error: cannot write " + tmp_);
  }
}

AtomicFile::~AtomicFile() {
  if (tmp_.empty()) return;
  out_.close();
  std::remove(tmp_.c_str());
  temp_files::forget(slot_);  // after the removal: a signal between the two finds nothing left behind
}

void AtomicFile::commit() {
  out_.flush();
  if (!out_) throw Error(ErrorKind::io, path_ + ": error: write failed (disk full?)");
  out_.close();
  if (have_old_) {
    // The file keeps what it was: mode, and owner where we may set it.
    ::chmod(tmp_.c_str(), old_mode_ & 07777);
    if (::chown(tmp_.c_str(), old_uid_, old_gid_) != 0) { /* not ours to give away: keep ours */ }
  } else {
    // Keep the permissions a new file would get (mkstemp creates 0600).
    const mode_t mask = ::umask(0);
    ::umask(mask);
    std::error_code ec;
    fs::permissions(tmp_, static_cast<fs::perms>(0666 & ~mask), ec);
  }
  if (std::rename(tmp_.c_str(), target_.c_str()) != 0)
    throw Error(ErrorKind::io, path_ + ": error: cannot rename the temporary file into place: " + std::strerror(errno));
  temp_files::forget(slot_);
  temp_files::completed(path_);
  tmp_.clear();
}

void write_file_atomically(const std::string& path, const std::string& input_path,
                           const std::function<void(std::ostream&)>& fill) {
  AtomicFile f(path, input_path);
  fill(f.stream());
  f.commit();
}

void write_through_temporary(std::ostream& out, const std::function<void(std::ostream&)>& fill) {
  std::string tmp = (fs::temp_directory_path() / "deflex-out-XXXXXX").string();
  const std::string tmpl = tmp;
  int slot = -1;
  const int fd = temp_files::create(tmp, slot);
  if (fd < 0) throw Error(ErrorKind::io, "error: cannot create a temporary file in " + tmpl + ": " + std::strerror(errno));
  ::close(fd);
  try {
    {
      std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
      fill(o);
      o.flush();
      if (!o) throw Error(ErrorKind::io, tmp + ": error: write failed (disk full?)");
    }
    std::ifstream i(tmp, std::ios::binary);
    if (i.peek() != std::ifstream::traits_type::eof()) out << i.rdbuf();  // nothing to copy is no failure
  } catch (...) {
    std::remove(tmp.c_str());
    temp_files::forget(slot);
    throw;
  }
  std::remove(tmp.c_str());
  temp_files::forget(slot);
}

}  // namespace deflex::writer

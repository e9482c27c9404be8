// Text held until it may go out (include/deflex/report/held_text.hpp).
#include "deflex/report/held_text.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <ostream>

#include "deflex/diag/diagnostics.hpp"

namespace deflex::report {

HeldText::~HeldText() {
  if (fd_ >= 0) ::close(fd_);
}

void HeldText::take(std::string&& chunk) {
  if (chunk.empty()) return;
  // Once text went to disk, all that follows does: the order is memory, then the file.
  if (fd_ < 0 && memory_ + chunk.size() <= memory_bytes_) {
    memory_ += chunk.size();
    chunks_.push_back(std::move(chunk));
  } else {
    spill(chunk);
  }
  chunk.clear();
}

void HeldText::spill(const std::string& chunk) {
  if (fd_ < 0) {
    namespace fs = std::filesystem;
    std::string tmpl = (fs::temp_directory_path() / ".deflex-held-XXXXXX").string();
    fd_ = ::mkstemp(tmpl.data());
    if (fd_ < 0) throw Error(ErrorKind::io, tmpl + ": error: cannot create a temporary file: " + std::strerror(errno));
    ::unlink(tmpl.c_str());  // gone with the process, whatever happens (as SpillBytes)
  }
  for (std::size_t done = 0; done < chunk.size();) {
    const ssize_t n = ::write(fd_, chunk.data() + done, chunk.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(ErrorKind::io, "temporary folder: error: write failed (disk full?)");
    done += static_cast<std::size_t>(n);
  }
  spilled_ += chunk.size();
}

void HeldText::write_to(std::ostream& o) {
  for (std::string& c : chunks_) {
    o.write(c.data(), static_cast<std::streamsize>(c.size()));
    std::string().swap(c);  // freed as it goes out
  }
  chunks_.clear();
  memory_ = 0;
  if (fd_ < 0) return;
  std::string buf(std::size_t{1} << 20, '\0');
  for (std::size_t at = 0; at < spilled_;) {
    const ssize_t n = ::pread(fd_, buf.data(), std::min(buf.size(), spilled_ - at), static_cast<off_t>(at));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw Error(ErrorKind::io, "error: cannot read back a temporary file");
    o.write(buf.data(), n);
    at += static_cast<std::size_t>(n);
  }
  ::close(fd_);
  fd_ = -1;
  spilled_ = 0;
}

}  // namespace deflex::report

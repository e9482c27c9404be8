// The registry of temporary files (include/deflex/writer/temp_files.hpp).
#include "deflex/writer/temp_files.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <cerrno>

#include <atomic>
#include <cstring>
#include <iterator>

namespace deflex::writer::temp_files {
namespace {

// A slot is free, being filled (by add), armed, or taken by the handler; a
// path is read only while armed or taken, and written only while being
// filled, so the handler never reads a path being written.
enum State : int { kFree, kFilling, kArmed, kTaken };

struct Slot {
  std::atomic<int> state{kFree};
  char path[4096];
};

// A run has a handful at once (an output, two report files, the summary and
// report.html, a stdout copy): room to spare.
Slot g_slots[64];
Slot g_done;  // the last completed output
std::atomic<bool> g_streaming{false};

bool fill(Slot& s, const std::string& path) {
  if (path.size() >= sizeof s.path) return false;
  std::memcpy(s.path, path.c_str(), path.size() + 1);
  return true;
}

}  // namespace

int add(const std::string& path) noexcept {
  for (int i = 0; i < static_cast<int>(std::size(g_slots)); ++i) {
    int free = kFree;
    if (!g_slots[i].state.compare_exchange_strong(free, kFilling)) continue;
    if (!fill(g_slots[i], path)) {
      g_slots[i].state.store(kFree);
      return -1;
    }
    g_slots[i].state.store(kArmed, std::memory_order_release);
    return i;
  }
  return -1;
}

int create(std::string& tmpl, int& slot) noexcept {
  slot = -1;
  for (int i = 0; i < static_cast<int>(std::size(g_slots)); ++i) {
    int free = kFree;
    if (!g_slots[i].state.compare_exchange_strong(free, kFilling)) continue;
    if (!fill(g_slots[i], tmpl)) {
      g_slots[i].state.store(kFree);
      break;
    }
    g_slots[i].state.store(kArmed, std::memory_order_release);
    const int fd = ::mkstemp(g_slots[i].path);
    if (fd < 0) {
      const int e = errno;
      forget(i);
      errno = e;
      return -1;
    }
    tmpl = g_slots[i].path;
    slot = i;
    return fd;
  }
  // No slot: the file is created all the same, unregistered.
  std::string name = tmpl;
  const int fd = ::mkstemp(name.data());
  if (fd >= 0) tmpl = name;
  return fd;
}

void forget(int slot) noexcept {
  if (slot < 0) return;
  // Taken: the handler is removing it and the process is ending.
  int armed = kArmed;
  g_slots[slot].state.compare_exchange_strong(armed, kFree);
}

void completed(const std::string& path) noexcept {
  int s = g_done.state.load();
  if (s == kTaken || !g_done.state.compare_exchange_strong(s, kFilling)) return;
  if (!fill(g_done, path)) {
    g_done.state.store(kFree);
    return;
  }
  g_done.state.store(kArmed, std::memory_order_release);
}

void streaming_stdout() noexcept { g_streaming.store(true); }

bool stdout_streamed() noexcept { return g_streaming.load(); }

void remove_all() noexcept {
  for (Slot& s : g_slots) {
    int armed = kArmed;
    if (s.state.compare_exchange_strong(armed, kTaken, std::memory_order_acquire)) ::unlink(s.path);
  }
}

const char* last_completed() noexcept {
  int armed = kArmed;
  return g_done.state.compare_exchange_strong(armed, kTaken, std::memory_order_acquire) ? g_done.path : nullptr;
}

}  // namespace deflex::writer::temp_files

// The signal handler (src/cli/signals.hpp). Everything it calls is
// async-signal-safe (POSIX.1-2017 2.4.3): unlink through the registry, write,
// _exit; it runs on whichever thread the signal reaches (the registry's
// header says why that is enough).
#include "signals.hpp"

#include <signal.h>
#include <unistd.h>

#include <cstring>

#include "deflex/writer/temp_files.hpp"

namespace deflex::cli {
namespace {

void say(const char* s) {
  for (std::size_t n = std::strlen(s); n > 0;) {
    const ssize_t w = ::write(2, s, n);
    if (w <= 0) return;
    s += w;
    n -= static_cast<std::size_t>(w);
  }
}

bool g_terminal = false;  // stderr: a progress line may stand unfinished

extern "C" void on_signal(int sig) {
  writer::temp_files::remove_all();
  say(g_terminal ? "\ndeflex: interrupted (" : "deflex: interrupted (");
  say(sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP");
  // A file renamed into place before the signal is whole (-o, then --report's
  // files): say so rather than "nothing written".
  if (const char* done = writer::temp_files::last_completed()) {
    say("): stopped after writing ");
    say(done);
    say("; temporary files removed\n");
  } else if (writer::temp_files::stdout_streamed()) {
    say("): standard output is cut short; temporary files removed\n");
  } else {
    say("): nothing written; temporary files removed\n");
  }
  ::_exit(128 + sig);
}

}  // namespace

void remove_temporaries_on_signals() {
  g_terminal = ::isatty(2);
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  // One handler at a time: a second signal waits for the _exit.
  sigemptyset(&sa.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&sa.sa_mask, s);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(s, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(s, &sa, nullptr);
  }
}

}  // namespace deflex::cli

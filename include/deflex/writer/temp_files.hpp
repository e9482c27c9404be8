// The temporary files deflex has on disk at any moment, for a signal handler
// to remove: AtomicFile's hidden sibling of each output (`.out.nc.deflex-*`,
// `rep/.points.csv.deflex-*`), the copy of a program bound for standard
// output (`$TMPDIR/deflex-out-*`), the solid stiffness model's mesh files and
// cache. (The report's spill files are unlinked as soon as they are open:
// nothing to remove.)
//
// Why a registry and not signals blocked in worker threads: TBB starts its
// workers itself, and a signal may reach any thread. The handler need not
// run on one thread in particular if all it does is async-signal-safe
// (POSIX.1-2017 2.4.3: unlink, write, _exit): so the registry is a fixed table
// of paths, filled and emptied with atomics, never allocating, and the
// handler unlinks what the table holds and ends the process with _exit, so no
// destructor or atexit handler runs beside the other threads.
#pragma once
#include <string>

namespace deflex::writer::temp_files {

// Registers `path` (as given to open(2); deflex never changes its folder) and
// returns its slot for forget(), or -1 when the table is full or the path too
// long (the file then goes only when its owner removes it).
int add(const std::string& path) noexcept;
// mkstemp(3) run in a registry slot: the file is the handler's from the
// instant it exists (registering it after mkstemp returned left an instant in
// which a signal found the file and not its name). `tmpl` ends in XXXXXX and
// gets the name chosen. Returns the open descriptor (-1 with errno on
// failure) and the slot in `slot` (-1 when the table is full or the path too
// long: the file then goes only when its owner removes it). While mkstemp
// writes the name the handler may unlink a name half written: a file that
// does not exist, or one of deflex's own leftovers.
int create(std::string& tmpl, int& slot) noexcept;
// The file is removed or renamed into place: no longer the handler's.
void forget(int slot) noexcept;
// An output is complete (renamed into place): the handler names the last one.
void completed(const std::string& path) noexcept;

// Standard output is being written as the work goes (path, rewrite): a
// signal leaves it cut short, which the handler says.
void streaming_stdout() noexcept;

// Async-signal-safe, for the handler: unlinks every registered file.
void remove_all() noexcept;
// Async-signal-safe: the last completed output, or nullptr.
const char* last_completed() noexcept;
// Async-signal-safe: whether streaming_stdout() was called.
bool stdout_streamed() noexcept;

}  // namespace deflex::writer::temp_files

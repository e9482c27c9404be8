// Ctrl-C, kill and a closed terminal: no temporary file left behind.
#pragma once

namespace deflex::cli {

// On SIGINT, SIGTERM and SIGHUP (each unless the parent left it ignored, as
// nohup does SIGHUP): removes every temporary file of writer/temp_files.hpp,
// prints one line on stderr and exits with 128 + the signal's number (130,
// 143, 129), as a shell reports a process the signal ended.
void remove_temporaries_on_signals();

}  // namespace deflex::cli

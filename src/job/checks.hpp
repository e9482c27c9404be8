// The steps of job::open() (open.cpp): the settings resolved and checked, the
// program checked whole or in pieces, the stock and the part model checked
// against it. Internal to src/job.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "deflex/diag/diagnostics.hpp"
#include "deflex/job/run.hpp"

namespace deflex::job::detail {

// The settings from the job and config.yaml, each checked (settings errors
// before anything is read or computed).
compensate::Settings settings_of(const Settings& a, const profile::Config& cfg, const profile::MachineProfile& mp);
// Settings that pass the range checks but leave the run meaningless, said
// before anything is read further (an error when strict).
void warn_meaningless(const compensate::Settings& st, bool strict, Io& io);
// A whole program's subprograms: written inline (Settings::expand_subprograms),
// the lines that run more than once, the calls.
void subprograms(Run& j, Io& io);
// The checks of a whole program: shape, decimal points, the interpretation,
// the travel and what each cutting motion needs; its motions into j.motions.
void check_whole(Run& j, Diagnostics& diags);
// The same on a program read in pieces, pass by pass, in the same order;
// `progress` (may be empty) gets the stage "checking" after each piece.
void check_in_pieces(Run& j, Diagnostics& diags, const compensate::Progress& progress);
// Settings::stock "auto[:MARGIN]": the blank box round the cutting moves (a note says so).
std::string auto_stock(const std::string& spec, const Run& j, Io& io);
// A warning (an error when strict) where no cutting move reaches the stock.
void check_stock_reached(const Run& j, Diagnostics& diags);
// The gouge check against the part model: warnings, and the moves that cut
// into the part stay as written (Run::gouge_lines).
void check_gouges(Run& j, Diagnostics& diags);
// The cutting moves of a program read in pieces, piece by piece in program
// order, interpreted again (a pass of its own; --spindle and --feed filled in).
void each_piece(Run& j, const std::function<void(std::vector<interp::Motion>&)>& fn);

// Verbose: the files and settings of a run, before it starts.
void print_setup(const Run& j, Io& io);

}  // namespace deflex::job::detail

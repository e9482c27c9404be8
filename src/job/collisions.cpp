// The tool assembly in the stock as errors (internal.hpp): compensate and
// simulate refuse a program whose holder, neck or shank runs into the
// material; check --stock finds the same by the sweep alone.
#include "deflex/compensate/collision.hpp"
#include "internal.hpp"

namespace deflex::job::detail {

void report_collisions(const Run& j, const std::vector<compensate::Collision>& cs, Diagnostics& diags) {
  std::vector<std::uint32_t> lines;
  for (const compensate::Collision& c : cs) lines.push_back(c.first_line);
  const auto text = lines_of_file(j, lines);
  for (const compensate::Collision& c : cs)
    diags.report(Severity::error, text.at(c.first_line), c.first_line, 1, c.message() + " [" + c.kind() + "]");
}

void refuse_collisions(const Run& j, const compensate::CollisionScan& scan, Io& io, const std::string& nothing) {
  if (!scan.any()) return;
  Diagnostics diags = io.diagnostics(0);
  report_collisions(j, scan.collisions(), diags);
  throw Error(ErrorKind::input, j.prog.source().name() + ": error: the tool assembly runs into the stock; " + nothing)
      .with_errors_of(diags);
}

std::vector<compensate::Collision> sweep_collisions(Run& j, const compensate::Progress& progress) {
  compensate::CollisionScan scan(j.physics.tools);
  const compensate::PointSink sink = [&](const compensate::Point& p) {
    scan.add(p, compensate::tool_id(p.tool, j.settings));
  };
  j.settings.geometry_only = true;
  // Nothing reads the initial stock after the sweep: it may cut it.
  j.physics.consumable_stock = j.stock.get();
  if (j.pieces) {
    compensate::PipelineInput in = pipeline_input(j, progress);
    in.sinks.nominal = sink;
    compensate::simulate_in_pieces(in);
  } else {
    compensate::simulate(j.motions, {}, j.physics, j.settings, sink, progress);
  }
  j.physics.stock = j.physics.consumable_stock = nullptr;
  return scan.collisions();
}

}  // namespace deflex::job::detail

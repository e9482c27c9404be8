// The workpiece's own compliance in a run (Settings::workholding): what
// job::open() reads and checks before the program, and the model it builds
// after every check. Internal to src/job.
#pragma once
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deflex/compensate/reach.hpp"
#include "deflex/job/run.hpp"
#include "deflex/job/workpiece.hpp"
#include "deflex/report/json.hpp"
#include "deflex/report/recorder.hpp"

namespace deflex::job::detail {

// The named material's elastic constants from the library; a config Error at
// the entry's line when it has none.
stiffness::Material elastic_of(const std::string& name, const std::string& library);

// What the workpiece model is built from, each part checked.
struct WorkpiecePlan {
  stiffness::PartSurface surface;
  std::vector<stiffness::Fixture> fixtures;
  stiffness::Material elastic;
  stiffness::WorkpieceOptions options;
  double spacing_mm = kDefaultFieldSpacingMm;  // the finest spacing tried
  bool spacing_given = false;                  // given: the only one tried
};

// The settings' checks, then the material's elastic constants, the part's
// surface (closed) and each fixture box touching it: nullopt without a fixture.
std::optional<WorkpiecePlan> plan_workpiece(const Run& j);

// Where the workpiece's stages begin (Workholding::stages; 0: one stage, the
// finished part), each stage's tool reach (widened by margin_mm), and staged,
// the in-process stock's surface when each begins (workpiece_stages.cpp).
struct StagePlan {
  std::vector<std::size_t> first_motion;  // program order, ascending, the first 0
  std::vector<std::uint32_t> first_line;
  std::vector<compensate::ToolReach> reach;
  std::vector<std::vector<stock::Triangle>> surfaces;  // staged only
  std::vector<std::vector<stock::BoxSpec>> solids;     // staged only: the stock as boxes (stock::zmap_boxes)
};
StagePlan plan_stages(Run& j, int stages, double margin_mm, double height_step_mm);

// The model (mesh, clamp, factorisation), its field over the surface the
// program's tools reach, checked against the FEM where the field is least
// sure; the model's memory is freed on return. Staged, one model and field
// per stage, the stock's surface meshed at the part's element size. `progress` gets the stage
// "workpiece". Null, with a warning, where no tool reaches the part.
std::shared_ptr<const WorkpieceInCut> build_workpiece(Run& j, const WorkpiecePlan& plan, Io& io,
                                                      const compensate::Progress& progress);

// summary.json's "workpiece" (null without one): the model, its field and
// check, the contacts outside the field, the tool's and the workpiece's
// largest share of the error; and the note that says them after a run.
report::Json workpiece_json(const Run& j, const report::RunFigures& f);
void print_workpiece_shares(const Run& j, const report::RunFigures& f, Io& io);
// report.html's key figures of the workpiece (none without one).
std::vector<std::vector<std::string>> workpiece_facts(const Run& j, const report::RunFigures& f);

}  // namespace deflex::job::detail

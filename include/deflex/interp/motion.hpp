// What the interpreter tells the rest of deflex: one call per tool motion, in
// the spirit of LinuxCNC's canonical machining functions, each carrying its
// source line and whether deflex may change it.
#pragma once
#include <vector>
#include <array>
#include <cstdint>

namespace deflex::interp {

using Vec3 = std::array<double, 3>;  // x, y, z

enum class MotionKind : std::uint8_t { rapid, linear, arc_cw, arc_ccw };

// Why a motion must never be compensated (first reason that applies).
enum class Fixed : std::uint8_t {
  no = 0,            // compensable cutting motion
  rapid,             // G0: not cutting
  cutter_comp,       // under G41/G42: the control offsets the path itself
  canned_cycle,      // expanded from a G73..G89 cycle
  subprogram,        // inside an M98 subprogram (one block, many places)
  incremental,       // G91: changing one block would shift all that follow
  machine_frame,     // G53 / G28 / G30 move in machine coordinates
  block_delete,      // `/` block: executed or not at the operator's switch
  // Set by compensation, never by the interpreter: a compensable move whose
  // end starts a block the writer cannot re-target (compensate::movable).
  held,
  // Set by the report for a point, never on a motion: a ball end's point
  // without a part model whose surface normal the program's points do not
  // determine (compensate::NormalSource::undetermined): not moved.
  no_normal,
  // Set from the gouge check (--part, compensate/gouge.hpp), never by the
  // interpreter: a cutting move that cuts into the part model. Its error is
  // the program's, not the tool's deflection: moving it would move a gouge.
  gouge,
};
const char* to_string(Fixed f);
const char* to_string(MotionKind k);  // "G0", "G1", "G2", "G3"

struct Motion {
  MotionKind kind = MotionKind::rapid;
  Fixed fixed = Fixed::rapid;
  std::uint8_t plane = 17;          // 17, 18 or 19 (arcs)
  std::uint32_t line = 0;           // source line of the commanding block
  Vec3 start_mm{};                  // tool tip, active work frame, mm
  Vec3 end_mm{};
  Vec3 center_mm{};                 // arcs: centre; its normal-axis value equals start's
  double feed_mm_per_min = 0.0;     // 0 for rapids
  int tool = 0;                     // active T number
  double spindle_rpm = 0.0;         // last S word (0: none yet)
  bool inch = false;                // the block was read in G20
  // A plain G0/G1/G2/G3 block (G90 or G91; under G41/G42 only in G90), on a
  // line that runs once, not block-deleted: one motion whose end is exactly
  // its X/Y/Z words (or the modal values; in G91 their sum with the
  // position), so the writer may re-target it by setting or adding words (a
  // G91 rapid after a compensated point takes the increment back to where
  // the original goes).
  bool plain = false;
  // G91: the block's X/Y/Z words are increments from where the control stands
  // (a plain G1 in G91 is compensable: the writer turns its ends into
  // increments from the written program's position, so every later position
  // stays the original's).
  bool incremental = false;
  // Offset of the active work frame in machine coordinates (work + this = machine), mm.
  Vec3 work_offset_mm{};
  // Under G41/G42 (comp: +1 left, -1 right; 0 off) the motion is the tool
  // centre's path, as the control computes it (interp/cutter_comp.hpp), and
  // contour_start_mm / contour_end_mm the block's programmed points, the
  // contour the control offsets.
  // corner: a piece the control adds at an outside corner (no block of its
  // own; its line is the block that ends at the corner).
  Vec3 contour_start_mm{}, contour_end_mm{};
  double comp_radius_mm = 0;  // the radius the control offsets by (D register)
  std::int8_t comp = 0;
  bool corner = false;
  bool compensable() const { return fixed == Fixed::no; }
  bool moves_xy() const { return start_mm[0] != end_mm[0] || start_mm[1] != end_mm[1]; }
};

class MotionSink {
 public:
  virtual ~MotionSink() = default;
  virtual void motion(const Motion& m) = 0;
};

// The motions into a list (a whole program's: see gcode::ProgramPasses for
// one that does not fit in memory).
class MotionList : public MotionSink {
 public:
  explicit MotionList(std::vector<Motion>& out) : out_(out) {}
  void motion(const Motion& m) override { out_.push_back(m); }

 private:
  std::vector<Motion>& out_;
};

}  // namespace deflex::interp

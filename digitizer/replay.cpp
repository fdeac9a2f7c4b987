#include "digitizer/replay.hpp"

namespace polarcam {

TapeReplay::TapeReplay(TapeReader& reader) : rd_(reader) {
  node_[0] = reader.header().start[0];
  node_[1] = reader.header().start[1];
}

bool TapeReplay::next(MachineStep& s) {
  StepRecord r;
  if (!rd_.next(r)) return false;
  t_ += r.interval;
  node_[r.axis] += r.dir;
  s.index = ++index_;
  s.t_ticks = t_;
  s.axis = r.axis;
  s.dir = r.dir;
  s.node[0] = node_[0];
  s.node[1] = node_[1];
  return true;
}

}  // namespace polarcam

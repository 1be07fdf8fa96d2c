// earl-m2t user file: pf tiago/a.cs.control/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "Harmoniser/tiago_a/cs/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::tiago_a::cs {

/// Passes the setpoints of the task agent present on to the base and the arm, reports the
/// robot and the person to it, and raises the fall alarm while the person lies on the floor.
/// Prints the number of each command it takes (one a period from its queue).
class control_pf final : public control_pf_base {
 public:
  using control_pf_base::control_pf_base;

  void execute() override {
    const auto& task = taskCommand_ib();
    if (taskCommand_ib_newData() && !harmoniser::quiet()) {
      std::printf("tiago/a.cs: took command %" PRId64 "\n", static_cast<std::int64_t>(task.seq));
    }
    baseCommand_ob() = task.base;
    armCommand_ob() = task.arm;
    robotStatus_ob().lastSeq = task.seq;
    robotStatus_ob().person = person_ib();
    fallAlarm_ob().fallen = person_ib().fallen;
  }
};

}  // namespace Harmoniser::tiago_a::cs

// earl-m2t user file: pf task/a.cs.sendCommand/pf
// The two-arm sample's user code (samples/two_arm/user). gen never overwrites it; if the pf
// disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "TwoArm/task_a/cs/data.hpp"
#include "two_arm_sample.hpp"

namespace TwoArm::task_a::cs {

/// Sends command number nextSeq + 1 with its setpoint to the arm in use; counts the commands
/// sent to that arm, from 1 again and one hand-over more after the 10th (handOver/pp then
/// switches to the other arm's configuration). task/a starts in withA, so the arm in use is
/// manipA/a after an even number of hand-overs. Prints
///   task/a.cs: sent seq N to manipA/a
class sendCommand_pf final : public sendCommand_pf_base {
 public:
  using sendCommand_pf_base::sendCommand_pf_base;

  static constexpr std::int64_t kPerArm = 10;

  void execute() override {
    // the memory this pf writes is also what it reads (the _mo accessors)
    if (sentToArm_mo() >= kPerArm) {
      sentToArm_mo() = 1;
      handOvers_mo() += 1;
    } else {
      sentToArm_mo() += 1;
    }
    const std::int64_t seq = nextSeq_mo() + 1;
    nextSeq_mo() = seq;
    auto& command = manipulatorCommand_ob();
    command.seq = seq;
    for (std::size_t j = 0; j < command.jointPosSetpoint.q.size(); ++j) {
      command.jointPosSetpoint.q[j] = two_arm::setpoint(seq, j);
    }
    if (!two_arm::quiet()) {
      std::printf("task/a.cs: sent seq %" PRId64 " to %s\n", seq, two_arm::kArms[handOvers_mo() % 2]);
    }
  }
};

}  // namespace TwoArm::task_a::cs

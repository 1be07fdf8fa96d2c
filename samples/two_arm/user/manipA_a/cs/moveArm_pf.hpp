// earl-m2t user file: pf manipA/a.cs.moveArm/pf
// The two-arm sample's user code (samples/two_arm/user). gen never overwrites it; if the pf
// disappears from the model, gen reports this file as orphaned.
#pragma once

#include <algorithm>
#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "TwoArm/manipA_a/cs/data.hpp"
#include "two_arm_sample.hpp"

namespace TwoArm::manipA_a::cs {

/// Takes a new command (newCommand/pp: its seq is beyond lastSeq) and moves the joints a step
/// of at most kMaxStep towards its setpoint; motionFinished once they are there. Prints
///   manipA/a.cs: took seq N
/// for each command taken (manipB/a.cs for the other arm), and before the first one since the
/// arm (re)started, its pf reset (reset(), which every runtime calls at a restart),
///   manipA/a.cs: reset before seq N
class moveArm_pf final : public moveArm_pf_base {
 public:
  using moveArm_pf_base::moveArm_pf_base;

  void execute() override {
    const auto& command = manipulatorCommand_ib();
    if (manipulatorCommand_ib_newData() && command.seq > lastSeq_mo()) {
      lastSeq_mo() = command.seq;
      target_ = command.jointPosSetpoint;
      if (!two_arm::quiet()) {
        if (reset_) std::printf("%s.cs: reset before seq %" PRId64 "\n", arm_, static_cast<std::int64_t>(command.seq));
        std::printf("%s.cs: took seq %" PRId64 "\n", arm_, static_cast<std::int64_t>(command.seq));
      }
      reset_ = false;
    }
    bool there = true;
    auto& q = jointPos_mo().q;
    for (std::size_t j = 0; j < q.size(); ++j) {
      const double gap = target_.q[j] - q[j];
      if (gap > two_arm::kMaxStep || gap < -two_arm::kMaxStep) {
        q[j] += std::clamp(gap, -two_arm::kMaxStep, two_arm::kMaxStep);
        there = false;
      } else {
        q[j] = target_.q[j];
      }
    }
    motionFinished_mo() = there;
  }

  /// A restart (the arm rejoins): no setpoint kept from before.
  void reset() noexcept {
    target_ = {};
    reset_ = true;
  }

 private:
  const char* arm_ = two_arm::nextArm();
  ::TwoArm::types::JointPosition target_{};
  bool reset_ = true;  // new, or reset(), and no command taken since
};

}  // namespace TwoArm::manipA_a::cs

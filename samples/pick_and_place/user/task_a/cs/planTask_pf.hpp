// earl-m2t user file: pf task/a.cs.planTask/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "PickAndPlace/task_a/cs/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::task_a::cs {

/// The sample's task, a script: in its first cycle it sends one joint move to kTarget (and
/// opens the gripper to kFingerOpen); once manip/a reports the motion finished it waits
/// kDwellCycles and commands an emergency stop to both agents. manip/a.cs then goes
/// idle -> jointMove -> idle -> emergencyStop, and its reported stop makes this subsystem
/// abort (taskAborted/pp), where holdCommands/pf keeps the stop.
///
/// A setpoint is sent in one cycle only: newJointPos/pp is newData(...jointPosSetpoint), true
/// for every fresh message that carries one, so repeating it would restart the motion
/// (jointMove -> jointMove). Later commands carry no setpoint.
///
/// Prints, with N this subsystem's cycles before this one:
///   step N task/a.cs: jointMove setpoint Q1 Q2 Q3 Q4 Q5 Q6
///   step N task/a.cs: motion finished
///   step N task/a.cs: emergency stop
class planTask_pf final : public planTask_pf_base {
 public:
  using planTask_pf_base::planTask_pf_base;

  static constexpr std::array<double, 6> kTarget{0.5, -0.4, 0.8, -0.3, 0.6, 0.2};  // rad
  static constexpr double kFingerOpen = 0.04;
  static constexpr std::uint64_t kDwellCycles = 100;

  void execute() override {
    auto& command = manipulatorCommand_ob();
    auto& gripper = gripperCommand_ob();
    command.jointPosSetpoint.clear();
    command.operationalPosSetpoint.clear();
    switch (phase_) {
      case Phase::move: {
        types::JointPosition setpoint{};
        setpoint.q = kTarget;
        command.jointPosSetpoint.push_back(setpoint);
        gripper.desiredFingerPos = kFingerOpen;
        trace("jointMove setpoint", &kTarget);
        phase_ = Phase::wait;
        break;
      }
      case Phase::wait:
        if (manipulatorState_ib().motionFinished) {
          trace("motion finished", nullptr);
          phase_ = Phase::dwell;
        }
        break;
      case Phase::dwell:
        if (++dwell_ >= kDwellCycles) {
          command.emergencyStopCommand = true;
          gripper.emergencyStopCommand = true;
          trace("emergency stop", nullptr);
          phase_ = Phase::stopped;
        }
        break;
      case Phase::stopped:
        break;
    }
    ++step_;
  }

 private:
  enum class Phase { move, wait, dwell, stopped };

  void trace(const char* what, const std::array<double, 6>* q) const noexcept {
    if (!trace_) return;
    if (q == nullptr) {
      std::printf("step %" PRIu64 " task/a.cs: %s\n", step_, what);
    } else {
      std::printf("step %" PRIu64 " task/a.cs: %s %.6f %.6f %.6f %.6f %.6f %.6f\n", step_, what, (*q)[0], (*q)[1],
                  (*q)[2], (*q)[3], (*q)[4], (*q)[5]);
    }
  }

  const bool trace_ = ::pick_and_place::traceEnabled();
  Phase phase_ = Phase::move;
  std::uint64_t dwell_ = 0;
  std::uint64_t step_ = 0;  // supervise/bb runs only this pf: once per cycle until the abort
};

}  // namespace PickAndPlace::task_a::cs

// earl-m2t user file: pf manip/a.cs.outputMotorCon/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "PickAndPlace/manip_a/cs/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::manip_a::cs {

/// Composes one MotorControllerCommand per joint (paper Fig. 14b): the winding current of
/// windingCurrentK/m, or zero current with the emergency stop set, and prints them:
///   step N manip/a.cs: i I1 I2 I3 I4 I5 I6 estop E
/// with the currents in A (N as in outputManipState/pf).
class outputMotorCon_pf final : public outputMotorCon_pf_base {
 public:
  using outputMotorCon_pf_base::outputMotorCon_pf_base;

  void execute() override {
    bool anyStop = false;
    for (std::size_t k = 0; k < motorControllerCommandK_ob_count; ++k) {
      const bool stop = emergencyStopCommandK_mi(k);
      auto& command = motorControllerCommandK_ob(k);
      command.emergencyStopCommand = stop;
      command.desiredWindingCurrent = stop ? 0.0 : windingCurrentK_mi(k);
      anyStop = anyStop || stop;
    }
    if (trace_) {
      std::printf("step %" PRIu64 " manip/a.cs: i %.6f %.6f %.6f %.6f %.6f %.6f estop %d\n", step_, current(0),
                  current(1), current(2), current(3), current(4), current(5), anyStop ? 1 : 0);
    }
    ++step_;
  }

 private:
  double current(std::size_t k) noexcept { return motorControllerCommandK_ob(k).desiredWindingCurrent; }

  const bool trace_ = ::pick_and_place::traceEnabled();
  std::uint64_t step_ = 0;  // stage 2 of every behaviour runs this pf: once per cycle
};

}  // namespace PickAndPlace::manip_a::cs

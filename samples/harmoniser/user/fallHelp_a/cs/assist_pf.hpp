// earl-m2t user file: pf fallHelp/a.cs.assist/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "Harmoniser/fallHelp_a/cs/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::fallHelp_a::cs {

/// Brings the robot next to the person and holds the arm out for them: one step more each
/// iteration. Prints
///   fallHelp/a.cs: assist step N (command M)
class assist_pf final : public assist_pf_base {
 public:
  using assist_pf_base::assist_pf_base;

  void execute() override {
    auto& command = taskCommand_ob();
    step_mo() += 1;
    command.base.vx = 0.2;
    command.arm.q[1] = 0.5;
    command.seq = ++seq_mo();
    if (!harmoniser::quiet()) std::printf("fallHelp/a.cs: assist step %" PRId64 " (command %" PRId64 ")\n", step_mo(), seq_mo());
  }
};

}  // namespace Harmoniser::fallHelp_a::cs

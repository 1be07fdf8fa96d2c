// earl-m2t user file: pf guide/a.cs.lead/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "Harmoniser/guide_a/cs/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::guide_a::cs {

/// Leads the person on to the next waypoint of the route (one more each iteration), the base
/// moving ahead slowly. Prints
///   guide/a.cs: lead to waypoint N (command M)
class lead_pf final : public lead_pf_base {
 public:
  using lead_pf_base::lead_pf_base;

  void execute() override {
    auto& command = taskCommand_ob();
    waypoint_mo() += 1;
    command.base.vx = 0.4;
    command.base.wz = 0.0;
    command.seq = ++seq_mo();
    if (!harmoniser::quiet()) std::printf("guide/a.cs: lead to waypoint %" PRId64 " (command %" PRId64 ")\n", waypoint_mo(), seq_mo());
  }
};

}  // namespace Harmoniser::guide_a::cs

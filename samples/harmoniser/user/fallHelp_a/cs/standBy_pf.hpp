// earl-m2t user file: pf fallHelp/a.cs.standBy/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "Harmoniser/fallHelp_a/cs/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::fallHelp_a::cs {

/// Stops the base and folds the arm. Prints
///   fallHelp/a.cs: stand by after command N
class standBy_pf final : public standBy_pf_base {
 public:
  using standBy_pf_base::standBy_pf_base;

  void execute() override {
    auto& command = taskCommand_ob();
    command.base = {};
    command.arm = {};
    command.seq = ++seq_mo();
    if (!harmoniser::quiet()) std::printf("fallHelp/a.cs: stand by after command %" PRId64 "\n", seq_mo());
  }
};

}  // namespace Harmoniser::fallHelp_a::cs

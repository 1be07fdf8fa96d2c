// earl-m2t user file: pf guide/a.cs.park/pf
// The harmoniser sample's user code (samples/harmoniser/user). gen never overwrites it; if the
// pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>

#include "Harmoniser/guide_a/cs/data.hpp"
#include "harmoniser_sample.hpp"

namespace Harmoniser::guide_a::cs {

/// Stops the base (the robot apologises to the person): the guiding is suspended, and waiting,
/// where this runs, is where a switch stops guide/a. Prints
///   guide/a.cs: park after command N
class park_pf final : public park_pf_base {
 public:
  using park_pf_base::park_pf_base;

  void execute() override {
    auto& command = taskCommand_ob();
    command.base = {};
    command.seq = ++seq_mo();
    if (!harmoniser::quiet()) std::printf("guide/a.cs: park after command %" PRId64 "\n", seq_mo());
  }
};

}  // namespace Harmoniser::guide_a::cs

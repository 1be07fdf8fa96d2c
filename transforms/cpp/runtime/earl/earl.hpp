// earl runtime: everything generated code uses. Header-only, C++17.
#pragma once

#include "earl/component.hpp"
#include "earl/health.hpp"
#include "earl/port.hpp"
#include "earl/realtime.hpp"
#include "earl/runner.hpp"
#include "earl/schedule.hpp"
#include "earl/subsystem.hpp"
#include "earl/trace.hpp"
#include "earl/types.hpp"
#include "earl/wake.hpp"

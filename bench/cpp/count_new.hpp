// A counting allocator for tests: count_new.cpp replaces the global operator new and
// operator delete (every form) with versions that count every call, and separately the calls
// made while counting is on.
#pragma once

#include <cstdint>

namespace count_new {

void start() noexcept;  // count from now on (after start-up)
void stop() noexcept;
std::uint64_t allocations() noexcept;    // operator new calls while counting
std::uint64_t deallocations() noexcept;  // operator delete calls while counting
std::uint64_t allAllocations() noexcept;  // operator new calls since the program started

}  // namespace count_new

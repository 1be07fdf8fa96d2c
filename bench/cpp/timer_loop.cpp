// bench/latency.py's idle baseline: the least a periodic thread costs on this machine. One
// thread sleeps to absolute deadlines 1 ms apart (clock_nanosleep, TIMER_ABSTIME) and does
// nothing else, for the given seconds: what a 1 kHz control loop costs with no work in it.
//
//   timer_loop SECONDS
#include <cstdio>
#include <cstdlib>
#include <ctime>

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 0.0;
  if (!(seconds > 0.0)) {
    std::fprintf(stderr, "usage: %s SECONDS\n", argv[0]);
    return 2;
  }
  timespec next{};
  clock_gettime(CLOCK_MONOTONIC, &next);
  const long long periods = static_cast<long long>(seconds * 1000.0);
  for (long long i = 0; i < periods; ++i) {
    next.tv_nsec += 1'000'000;
    if (next.tv_nsec >= 1'000'000'000) {
      next.tv_nsec -= 1'000'000'000;
      ++next.tv_sec;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr) != 0) {
    }
  }
  return 0;
}

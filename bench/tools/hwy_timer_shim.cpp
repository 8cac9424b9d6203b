// Valgrind 3.19 cannot decode RDTSCP, which libhwy (linked into Blender through libjxl) executes in
// a static initialiser on CPUs that have it, so Blender dies with SIGILL under callgrind. Preloading
// this library interposes libhwy's exported timer queries with ones that do not use RDTSCP; nothing
// of ours calls them, so instruction counts of the engine are unchanged.
#include <chrono>
#include <cstdint>

namespace hwy {
namespace platform {
uint64_t TimerResolution() { return 1; }
double InvariantTicksPerSecond() { return 1e9; }
double Now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace platform
}  // namespace hwy

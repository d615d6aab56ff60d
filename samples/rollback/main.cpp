// rengine-rollback: two peers play the arena over a simulated link with delay and jitter,
// rolling back and simulating again whenever a late input proves a prediction wrong, and a
// reference that never rolls back plays the true inputs. Prints the rollbacks and whether
// every confirmed frame's world hash agrees on the three (exit 1 if not).
//
//   build/bin/rengine-rollback [--frames 1200] [--delay 3] [--jitter 4] [--seed 1]
//                              [--max-prediction 8] [--threads-b 1]
#include "Session.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

long Number(const char* name, const char* text, long lowest) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < lowest) {
    std::fprintf(stderr, "rengine-rollback: %s takes an integer >= %ld (got \"%s\")\n", name, lowest, text);
    std::exit(2);
  }
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  long frames = 1200, prediction = 8, threadsB = 1;
  rollback::LinkSettings link;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (k + 1 >= argc) {
      std::fprintf(stderr, "usage: rengine-rollback [--frames N] [--delay T] [--jitter T] [--seed S] "
                           "[--max-prediction F] [--threads-b N]\n");
      return 2;
    }
    const char* value = argv[++k];
    if (arg == "--frames") frames = Number("--frames", value, 1);
    else if (arg == "--delay") link.delay = static_cast<int>(Number("--delay", value, 0));
    else if (arg == "--jitter") link.jitter = static_cast<int>(Number("--jitter", value, 0));
    else if (arg == "--seed") link.seed = static_cast<std::uint64_t>(Number("--seed", value, 0));
    else if (arg == "--max-prediction") prediction = Number("--max-prediction", value, 1);
    else if (arg == "--threads-b") threadsB = Number("--threads-b", value, 0);
    else {
      std::fprintf(stderr, "rengine-rollback: unknown option %s\n", arg.c_str());
      return 2;
    }
  }
  const rollback::SessionResult r = rollback::PlaySession(static_cast<std::uint64_t>(frames), link,
                                                          static_cast<std::size_t>(prediction), static_cast<int>(threadsB));
  std::printf("%llu frames in %llu ticks, link %d + up to %d ticks\n", static_cast<unsigned long long>(r.frames),
              static_cast<unsigned long long>(r.ticks), link.delay, link.jitter);
  std::printf("rollbacks %zu, frames simulated again %zu, deepest %zu, ticks waited %zu\n", r.rollbacks,
              r.resimulated, r.deepest, r.stalls);
  std::printf("shots in flight at most %zu, bodies asleep at most %zu\n", r.mostShots, r.mostAsleep);
  if (r.firstMismatch) {
    std::printf("MISMATCH: frame %llu differs from the reference\n", static_cast<unsigned long long>(r.firstMismatch));
    return 1;
  }
  std::printf("every confirmed frame's world hash agrees on both peers and the reference (last %016llx)\n",
              static_cast<unsigned long long>(r.reference.back()));
  return 0;
}

// minksum haptics: the 1 kHz loop with its latency table (and, on request, its plot).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "commands.hpp"
#include "haptics/loop.hpp"

namespace minksum::cli {

int cmd_haptics(int argc, char** argv) {
  haptics::Options o;
  std::string png;
  bool json = false;
  for (int k = 0; k < argc; ++k) {
    const std::string a = argv[k];
    const auto value = [&](std::string& out) {
      if (k + 1 >= argc) return false;
      out = argv[++k];
      return true;
    };
    std::string v;
    if (a == "--json") {
      json = true;
    } else if (a == "--realtime") {
      o.realtime = true;
    } else if (a == "--tool" || a == "--scene" || a == "--plot") {
      if (!value(v)) return usage_error(a + " needs a value");
      (a == "--tool" ? o.tool : a == "--scene" ? o.scene : png) = v;
    } else if (a == "--seconds" || a == "--rate") {
      if (!value(v)) return usage_error(a + " needs a value");
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (*end != '\0' || !(x > 0)) return usage_error(a + ": '" + v + "' is not a positive number");
      (a == "--seconds" ? o.seconds : o.rate) = x;
    } else {
      return usage_error("unknown option '" + a + "'");
    }
  }
  haptics::Report r;
  std::string error;
  if (!haptics::run(o, haptics::allocation_count, r, error)) {
    std::fprintf(stderr, "minksum: %s\n", error.c_str());
    return 2;
  }
  if (json) {
    std::printf("{\"ticks\": %ld, \"p50_us\": %.2f, \"p99_us\": %.2f, \"p999_us\": %.2f, \"max_us\": %.2f, "
                "\"misses\": %ld, \"allocations\": %ld, \"exceptions\": %ld, \"contacts\": %ld, \"realtime_priority\": %s, "
                "\"max_late_start_us\": %.1f}\n",
                r.ticks, r.p50_us, r.p99_us, r.p999_us, r.max_us, r.misses, r.allocations, r.exceptions, r.contacts,
                r.realtime_priority ? "true" : "false", r.max_late_start_us);
  } else {
    std::printf("haptics: %s on %s, %ld ticks at %.0f Hz (%s)\n", r.tool_name.c_str(), r.scene_source.c_str(),
                r.ticks, o.rate,
                !o.realtime ? "back to back" : r.realtime_priority ? "paced, SCHED_FIFO" : "paced, normal priority");
    std::printf("tick latency p50 %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us; %ld missed deadlines\n",
                r.p50_us, r.p99_us, r.p999_us, r.max_us, r.misses);
    if (o.realtime) std::printf("latest start after its tick time %.1f us (scheduling jitter)\n", r.max_late_start_us);
    std::printf("allocations after warm-up %ld, exceptions %ld, ticks in contact %ld\n", r.allocations,
                r.exceptions, r.contacts);
  }
  if (!png.empty() && !haptics::plot(r, png, error)) {
    std::fprintf(stderr, "minksum: %s\n", error.c_str());
    return 2;
  }
  return 0;
}

}  // namespace minksum::cli

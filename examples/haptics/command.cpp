// minksum haptics: the 1 kHz loop with its latency table (and, on request, its plot).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <string>

#include "commands.hpp"
#include "haptics/loop.hpp"

namespace minksum::cli {

int cmd_haptics(int argc, char** argv) {
  haptics::Options o;
  std::string png, trace;
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
    } else if (a == "--tool" || a == "--scene" || a == "--plot" || a == "--trace") {
      if (!value(v)) return usage_error(a + " needs a value");
      (a == "--tool" ? o.tool : a == "--scene" ? o.scene : a == "--plot" ? png : trace) = v;
    } else if (a == "--seconds" || a == "--rate" || a == "--press" || a == "--speed" || a == "--slide") {
      if (!value(v)) return usage_error(a + " needs a value");
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      const bool zero_ok = a == "--slide" || a == "--press";  // (0: in place, or just touching)
      if (*end != '\0' || !(zero_ok ? x >= 0 : x > 0) || !std::isfinite(x))
        return usage_error(a + ": '" + v + "' is not a " + (zero_ok ? "non-negative" : "positive") + " number");
      if (a == "--rate" && !(x >= 1 && x <= 1e5)) return usage_error("--rate: " + v + " Hz is outside [1, 100000] Hz");
      (a == "--seconds" ? o.seconds : a == "--rate" ? o.rate : a == "--press" ? o.press : a == "--slide" ? o.slide : o.speed) =
          a == "--press" || a == "--slide" ? x / 1000 : x;
    } else {
      return usage_error("unknown option '" + a + "'");
    }
  }
  // The output files are checked before the run (a minute of ticks, then a path that fails).
  for (const std::string* path : {&png, &trace}) {
    if (path->empty()) continue;
    FILE* f = std::fopen(path->c_str(), "w");
    if (!f) return usage_error((path == &png ? "--plot " : "--trace ") + *path + ": cannot write there");
    std::fclose(f);
  }
  // The same path twice: every tick cold, then with the caches (the loop as it runs).
  haptics::Report cold, r;
  std::string error;
  o.coherent = false;
  const bool ran = haptics::run(o, haptics::allocation_count, cold, error);
  o.coherent = true;
  if (!ran || !haptics::run(o, haptics::allocation_count, r, error)) {
    std::fprintf(stderr, "minksum: %s\n", error.c_str());
    return 2;
  }
  if (json) {
    std::printf(
        "{\"ticks\": %ld, \"p50_us\": %.2f, \"p99_us\": %.2f, \"p999_us\": %.2f, \"max_us\": %.2f, "
        "\"cpu_p999_us\": %.2f, \"cpu_max_us\": %.2f, \"misses\": %ld, \"late_starts\": %ld, "
        "\"overruns\": %ld, \"allocations\": %ld, \"exceptions\": %ld, \"contacts\": %ld, \"sweeps\": %ld, "
        "\"max_force_jump_n\": %.4f, \"max_torque_jump_nm\": %.6f, "
        "\"realtime_priority\": %s, \"max_late_start_us\": %.1f, \"cold\": {\"p50_us\": %.2f, "
        "\"p99_us\": %.2f, \"p999_us\": %.2f, \"max_us\": %.2f, \"cpu_p999_us\": %.2f, \"misses\": %ld}}\n",
        r.ticks, r.p50_us, r.p99_us, r.p999_us, r.max_us, r.cpu_p999_us, r.cpu_max_us, r.misses, r.late_starts,
        r.overruns, r.allocations, r.exceptions, r.contacts, r.sweeps, r.max_force_jump, r.max_torque_jump,
        r.realtime_priority ? "true" : "false",
        r.max_late_start_us, cold.p50_us, cold.p99_us, cold.p999_us, cold.max_us, cold.cpu_p999_us, cold.misses);
  } else {
    std::printf("haptics: %s on %s, %ld ticks at %.0f Hz (%s), the same path cold and coherent\n", r.tool_name.c_str(),
                r.scene_source.c_str(), r.ticks, o.rate,
                !o.realtime           ? "back to back"
                : r.realtime_priority ? "paced, SCHED_FIFO"
                                      : "paced, normal priority");
    std::printf("%-26s %9s %9s %9s %9s\n", "tick latency [us]", "p50", "p99", "p99.9", "max");
    for (const haptics::Report* x : {&cold, &r}) {
      const char* name = x == &cold ? "cold" : "coherent";
      std::printf("%-9s wall clock       %9.1f %9.1f %9.1f %9.1f\n", name, x->p50_us, x->p99_us, x->p999_us, x->max_us);
      std::printf("%-9s thread CPU time  %9.1f %9.1f %9.1f %9.1f\n", name, x->cpu_p50_us, x->cpu_p99_us, x->cpu_p999_us,
                  x->cpu_max_us);
    }
    for (const haptics::Report* x : {&cold, &r}) {
      const char* name = x == &cold ? "cold" : "coherent";
      if (o.realtime)
        std::printf("%s: %ld missed deadlines, %ld ticks started over 50 us late by the OS (latest %.1f us)", name,
                    x->misses, x->late_starts, x->max_late_start_us);
      else  // (no schedule, so no deadline: the ticks that would have missed one)
        std::printf("%s: %ld ticks longer than the period on the wall clock", name, x->misses);
      std::printf(", %ld ticks whose own CPU time overran the period\n", x->overruns);
    }
    std::printf("allocations after warm-up %ld and %ld, exceptions %ld and %ld, ticks in contact %ld, swept %ld\n",
                cold.allocations, r.allocations, cold.exceptions, r.exceptions, r.contacts, r.sweeps);
    std::printf("in steady contact the force changed by at most %.3f N and the torque by %.3f N mm a tick\n",
                r.max_force_jump, 1000 * r.max_torque_jump);
  }
  if (!trace.empty()) {  // per tick, both runs: for plots of cold against coherent
    FILE* f = std::fopen(trace.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "minksum: %s: cannot write\n", trace.c_str());
      return 2;
    }
    std::fprintf(f, "tick,cold_wall_us,cold_cpu_us,coherent_wall_us,coherent_cpu_us,contact\n");
    for (size_t k = 0; k < std::min(r.latency_us.size(), cold.latency_us.size()); ++k)
      std::fprintf(f, "%zu,%.3f,%.3f,%.3f,%.3f,%d\n", k, cold.latency_us[k], cold.cpu_us[k], r.latency_us[k],
                   r.cpu_us[k], int(r.depth[k] > 0));
    std::fclose(f);
  }
  if (!png.empty() && !haptics::plot(r, png, error)) {
    std::fprintf(stderr, "minksum: %s\n", error.c_str());
    return 2;
  }
  return 0;
}

}  // namespace minksum::cli

// A 1 kHz 6-DOF haptic servo loop on minksum, as a device application would run it: everything
// sized at set-up, then per tick a proxy swept towards the device pose (time of impact), the
// contact patch at the proxy, and the force and torque that patch transmits.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace minksum::haptics {

/// What to run.
struct Options {
  /// "sphere:R", "capsule:H:R" (mm; half length H along the tool's z), "box", "icosa", or a
  /// mesh file (its convex hull is the tool)
  std::string tool = "sphere:5";
  /// mesh file; empty: bunny res2; "bunny_full": the full bunny (or their fallbacks); "sheet":
  /// a 60 mm square sheet 0.5 mm thick; "bumpy_full": the full bunny's generated stand-in always
  std::string scene;
  double seconds = 60;       ///< simulated time
  double press = 0.002;      ///< how far the device is pressed below touching the scene [m] (< 0: above)
  double slide = 0.008;      ///< how far it slides each way while turning [m] (0: it turns in place)
  double speed = 0;          ///< > 0: the device plunges straight down at this speed [m/s]
  double stiffness = 2000;   ///< the virtual coupling's spring from the device to the proxy [N/m]
  double damping = 5;        ///< and its damper on the device's approach speed [N s/m]
  double rate = 1000;        ///< ticks per second
  bool realtime = false;     ///< pace ticks with sleep-until and count missed deadlines
  bool coherent = true;      ///< start each tick's mesh distance from the last tick's answer
  int warmup = 1000;         ///< ticks before allocations are counted
  /// Ticks whose per-tick values the report keeps (the first ones): a run's memory is fixed,
  /// whatever its length; its percentiles and counts cover every tick.
  long traced = 10000;
};

/// Tick latencies in fixed memory, whatever the run's length (HdrHistogram's layout, Tene 2012):
/// 0.01 us steps up to 10.24 us, then 512 steps per doubling (0.2 %) up to 1.7e8 us.
class Latencies {
 public:
  /// Adds one tick's latency [us].
  void add(double us);
  /// The q-quantile (the tick at rank floor(q n) of n): its bucket's upper edge, at most the max.
  double percentile(double q) const;
  /// The largest latency added.
  double max() const { return max_; }

 private:
  static constexpr int kSub = 512, kBuckets = 2 * kSub + 24 * kSub;
  std::vector<unsigned> count_ = std::vector<unsigned>(kBuckets, 0);
  long n_ = 0;
  double max_ = 0;
};

/// What one run measured, with per-tick traces for plots and tests.
struct Report {
  std::string scene_source, tool_name;
  long ticks = 0;
  double p50_us = 0, p99_us = 0, p999_us = 0, max_us = 0;  ///< tick latency (wall clock)
  /// The same percentiles of the tick's own CPU time (CLOCK_THREAD_CPUTIME_ID): what the tick
  /// computed, without the time the OS gave to others while it ran.
  double cpu_p50_us = 0, cpu_p99_us = 0, cpu_p999_us = 0, cpu_max_us = 0;
  /// Paced: ticks that ended after their deadline; back to back: ticks longer than the period
  long misses = 0;
  long late_starts = 0;            ///< ticks the OS started over 50 us after their time (realtime only)
  long overruns = 0;               ///< ticks whose own CPU time exceeded the period (ours, not the OS's)
  double max_late_start_us = 0;    ///< worst start after the tick's time (realtime: OS jitter)
  long allocations = 0;            ///< heap allocations inside the loop after warm-up (-1: not counted)
  long exceptions = 0;             ///< exceptions caught around ticks
  long contacts = 0;               ///< ticks with the tool touching or pressing into the scene
  long sweeps = 0;                 ///< times of impact computed (the others were certified free)
  /// The largest change of the force [N] and of the torque [N m] from one tick to the next,
  /// both in contact after the first tick of contact (an impact's first tick jumps by design)
  double max_force_jump = 0, max_torque_jump = 0;
  bool realtime_priority = false;  ///< a paced run got SCHED_FIFO
  /// Per tick, for the first Options::traced ticks: the proxy's distance to the scene, the
  /// device's depth past the proxy along the contact normal, |force|, latency
  std::vector<double> time, distance, depth, force, latency_us;
  std::vector<double> torque;                                    ///< per tick: |torque| about the device's origin
  std::vector<double> device_y, proxy_y;                         ///< per tick: the origins' heights
  std::vector<double> cpu_us;                                    ///< per tick: its thread CPU time
  std::vector<double> force_dot_normal;                          ///< force . push-out direction (>= 0)
  std::vector<double> force_up;                                  ///< force . +y (the press is straight down along -y)
  std::vector<Eigen::Isometry3d> proxy;                          ///< per tick: the proxy's pose after its move
  std::string scene_mesh;  ///< the scene's mesh file as demo_mesh names it ("" for a file or the sheet)
};

/// How far the proxy may come into the scene: the tolerance of its sweeps (time_of_impact's band
/// contract: no hit farther than it), a quarter of the skin it rests at.
constexpr double kProxyTolerance = 5e-5 / 4;

/// Heap allocations of this executable so far, counted by alloc_count.cpp (which replaces
/// malloc and operator new when linked in), or -1 where they are not counted (sanitizer builds).
long allocation_count();

/// Runs the loop. `allocations` reads the executable's allocation counter (it replaces
/// operator new and malloc). False with a one-line `error` for bad options or files.
bool run(const Options& options, long (*allocations)(), Report& report, std::string& error);

/// Draws distance, depth, force and torque along the path and a latency histogram into a PNG (gnuplot).
bool plot(const Report& report, const std::string& png, std::string& error);

}  // namespace minksum::haptics

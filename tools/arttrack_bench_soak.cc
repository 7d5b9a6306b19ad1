#include "arttrack_bench_soak.h"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "arttrack/sim/scenario_runner.h"
#include "arttrack/tracker/error.h"
#include "arttrack/tracker/tracker.h"

namespace arttrack::cli {
namespace {

constexpr int kJointRateHz = 1000;
constexpr int kImageRateHz = 30;

// Resident memory of this process, kB (/proc/self/status VmRSS).
long resident_kb() {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  throw InputError("/proc/self/status: no VmRSS line (not Linux?)");
}

// The first images of a run and the encoder readings up to them.
class Recorder : public sim::MeasurementSink {
 public:
  explicit Recorder(int frames) : frames_(frames) {}
  void begin_run(const sim::RunStart& start) override { start_ = start; }
  void joints(int, double, std::span<const double> readings_rad) override {
    if (int(images_.size()) < frames_)
      readings_.emplace_back(readings_rad.begin(), readings_rad.end());
  }
  void image(int, double, double, const DepthImage& image) override {
    if (int(images_.size()) < frames_) images_.push_back(image);
  }

  const sim::RunStart& start() const { return start_; }
  const std::vector<std::vector<double>>& readings() const { return readings_; }
  const std::vector<DepthImage>& images() const { return images_; }

 private:
  int frames_;
  sim::RunStart start_;
  std::vector<std::vector<double>> readings_;
  std::vector<DepthImage> images_;
};

}  // namespace

void run_soak(sim::Scenario scenario, std::shared_ptr<const RobotModel> robot,
              const TrackerConfig& config, const SoakOptions& options) {
  if (!(options.minutes >= 1 && options.minutes <= 24 * 60))
    throw InputError("--soak: minutes must be between 1 and 1440");
  // The recording: 1 kHz encoders, 30 Hz images, a little longer than the frames.
  scenario.joint_rate_hz = kJointRateHz;
  scenario.camera_timing.rate_hz = kImageRateHz;
  scenario.duration_s = scenario.camera_timing.first_frame_s + scenario.camera_timing.latency_s +
                        double(options.frames + 1) / kImageRateHz;
  Recorder recorder(options.frames);
  sim::RunOptions run;
  run.runs = 1;
  run.seed = options.seed;
  run.methods = {method_name(TrackingMethod::kEncodersOnly)};
  run.frames_to_keep = 0;
  run.sink = &recorder;
  sim::run_scenario(scenario, run);
  if (recorder.images().empty() || recorder.readings().empty())
    throw InputError(scenario.source + ": the recording gave no images to soak with");

  Tracker tracker(robot, config, recorder.start().encoder_joints);
  const std::vector<std::vector<double>>& readings = recorder.readings();
  const std::vector<DepthImage>& images = recorder.images();
  const long long joint_steps = std::llround(options.minutes * 60 * kJointRateHz);
  const long long steps_per_minute = 60LL * kJointRateHz;
  long long next_image = 0;  // index of the next 30 Hz image
  long rss_minute_kb = 0;
  TrackerEstimate estimate;  // kept: filling it again allocates nothing
  const auto start = std::chrono::steady_clock::now();
  std::cout << "arttrack bench --soak: " << options.minutes << " min of " << kJointRateHz
            << " Hz joints and " << kImageRateHz << " Hz images (" << images.size()
            << " distinct) into one tracker, resident memory at start " << resident_kb() << " kB\n";
  for (long long step = 1; step <= joint_steps; ++step) {
    // Integer counters: the clocks advance exactly, however long the run.
    const double t_s = double(step) / kJointRateHz;
    tracker.add_joint_measurement(t_s, readings[std::size_t(step) % readings.size()]);
    // Images arrive once the joints have reached their stamp.
    while (next_image * kJointRateHz <= step * kImageRateHz) {
      tracker.add_depth_image(double(next_image) / kImageRateHz,
                              images[std::size_t(next_image) % images.size()],
                              recorder.start().camera);
      ++next_image;
      tracker.estimate(estimate);  // read as a controller would, at every image
    }
    if (step % steps_per_minute != 0) continue;
    const long long minute = step / steps_per_minute;
    if (minute == 1) rss_minute_kb = resident_kb();
    if (minute == 1 || minute % 10 == 0 || step == joint_steps) {
      const double wall_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::ostringstream elapsed;
      elapsed << std::fixed << std::setprecision(1) << wall_s;
      std::cout << "  minute " << minute << ": VmRSS " << resident_kb() << " kB, " << elapsed.str()
                << " s elapsed" << std::endl;
    }
  }
  const long end_kb = resident_kb();
  const TrackerStats stats = tracker.stats();
  const long growth_kb = end_kb - rss_minute_kb;
  std::cout << "  end (" << options.minutes << " min): VmRSS " << end_kb
            << " kB, growth since minute 1 " << growth_kb << " kB; " << stats.joint_measurements
            << " joint readings, " << stats.images_applied << " of " << stats.images_received
            << " images applied\n";
  if (growth_kb > options.max_growth_mb * 1024) {
    std::ostringstream os;
    os << "--soak: resident memory grew by " << growth_kb << " kB from minute 1 to the end, over "
       << options.max_growth_mb * 1024 << " kB";
    throw InputError(os.str());
  }
}

}  // namespace arttrack::cli

// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Small helpers shared by the benchmark programs: timing, peak memory,
// statistics and markdown tables.

#include <chrono>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/dataset.h"
#include "handeye/sim/synthetic.h"

namespace handeye::bench {

/// Wall-clock seconds since construction.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double Seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// Peak resident set size of this process (MiB), from /proc/self/status VmHWM.
double PeakRssMiB();
/// Resets the peak so the next PeakRssMiB() measures one stage (Linux
/// /proc/self/clear_refs); returns false where the kernel does not allow it.
bool ResetPeakRss();

double Mean(const std::vector<double>& v);
double Median(std::vector<double> v);
/// sqrt(mean(v²)).
double Rms(const std::vector<double>& v);

/// Predicted over reported ratios, as the plan benches table them:
/// "median (min, max)", and "N/M" of them within 30 % of 1 (0.7–1.3).
std::string RatioRange(const std::vector<double>& ratios);
std::string RatiosWithin30Percent(const std::vector<double>& ratios);

/// A markdown table: header cells, then rows added one at a time.
class Table {
 public:
  explicit Table(std::vector<std::string> header) : header_(std::move(header)) {}
  void Add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  std::string Markdown() const;

 private:
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

/// printf-style formatting into a std::string.
std::string Format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

/// Detected points against the true pixels of the same ids.
struct DetectionError {
  double sigma_px = 0;  ///< robust σ per coordinate (1.4826 · median |error|)
  double max_px = 0;    ///< largest point error
  int gross = 0;        ///< points off by more than 1 px
  int points = 0;
};
DetectionError MeasureDetectionError(const SyntheticScene& scene);

/// Splits "a,b,c".
std::vector<std::string> SplitList(const std::string& text);

/// Given intrinsics off as an earlier calibration may leave them (the
/// benches' --intrinsics-off PCT/PX): focal length by PCT %, principal point
/// by PX pixels.
struct IntrinsicsOffset {
  double focal_percent = 0;
  double principal_point_px = 0;
};
/// "PCT/PX" (e.g. "1/3"); false when it is not two numbers.
bool ParseIntrinsicsOffset(const std::string& text, IntrinsicsOffset* offset);
/// Moves every camera's given intrinsics by `offset`, alternately: even
/// cameras fx, fy × (1 + PCT/100), cx + PX, cy − PX; odd cameras the other
/// way. The observations keep the true cameras'.
void OffsetIntrinsics(const IntrinsicsOffset& offset, Dataset* dataset);

}  // namespace handeye::bench

namespace handeye::bench {

/// One image's detection, timed: CPU seconds of the whole process (so OpenCV's
/// own worker threads count) spent decoding it and detecting in it.
struct ImageTiming {
  std::string pose_id, camera;
  bool found = false;
  double load_cpu_s = 0;
  double detect_cpu_s = 0;
};

/// Detects in every image of `dataset` one after the other on the calling
/// thread, timing each (ImageTiming), and replaces dataset->observations with
/// what was found, in pose then camera order as DetectAll() does.
std::vector<ImageTiming> DetectTimed(Dataset* dataset);

/// Per-image CPU milliseconds of one class of images (with or without the
/// target): count, mean / median / 90th percentile / max of decode + detect,
/// and the mean of decode alone.
struct ClassTiming {
  int images = 0;
  double mean_ms = 0, median_ms = 0, p90_ms = 0, max_ms = 0, mean_load_ms = 0;
};
ClassTiming SummariseTimings(const std::vector<ImageTiming>& timings, bool found);

}  // namespace handeye::bench

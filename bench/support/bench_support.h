// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
// Small helpers shared by the benchmark programs: timing, peak memory,
// statistics and markdown tables.

#include <chrono>
#include <string>
#include <vector>

#include "handeye/core/calibration.h"
#include "handeye/core/synthetic.h"

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

}  // namespace handeye::bench

// SPDX-License-Identifier: GPL-2.0-or-later
#include "support/bench_support.h"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "handeye/detectors/registry.h"
#include "handeye/io/image.h"

namespace handeye::bench {

double PeakRssMiB() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

bool ResetPeakRss() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  return static_cast<bool>(clear);
}

double Mean(const std::vector<double>& v) {
  if (v.empty()) return 0.0;
  double sum = 0;
  for (double x : v) sum += x;
  return sum / v.size();
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double Rms(const std::vector<double>& v) {
  if (v.empty()) return 0.0;
  double sum = 0;
  for (double x : v) sum += x * x;
  return std::sqrt(sum / v.size());
}

std::string RatioRange(const std::vector<double>& ratios) {
  if (ratios.empty()) return "-";
  const auto [lo, hi] = std::minmax_element(ratios.begin(), ratios.end());
  return Format("%.2f (%.2f, %.2f)", Median(ratios), *lo, *hi);
}

std::string RatiosWithin30Percent(const std::vector<double>& ratios) {
  const auto within =
      std::count_if(ratios.begin(), ratios.end(), [](double r) { return r >= 0.7 && r <= 1.3; });
  return Format("%d/%d", static_cast<int>(within), static_cast<int>(ratios.size()));
}

std::string Table::Markdown() const {
  std::vector<size_t> width(header_.size(), 3);
  for (size_t c = 0; c < header_.size(); ++c) width[c] = std::max(width[c], header_[c].size());
  for (const auto& row : rows_)
    for (size_t c = 0; c < row.size() && c < width.size(); ++c)
      width[c] = std::max(width[c], row[c].size());
  std::ostringstream out;
  auto line = [&](const std::vector<std::string>& cells) {
    out << "|";
    for (size_t c = 0; c < width.size(); ++c) {
      const std::string cell = c < cells.size() ? cells[c] : "";
      out << " " << cell << std::string(width[c] - cell.size(), ' ') << " |";
    }
    out << "\n";
  };
  line(header_);
  out << "|";
  for (size_t w : width) out << std::string(w + 2, '-') << "|";
  out << "\n";
  for (const auto& row : rows_) line(row);
  return out.str();
}

std::string Format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buf, sizeof(buf), fmt, args);
  va_end(args);
  return buf;
}

DetectionError MeasureDetectionError(const SyntheticScene& scene) {
  std::vector<double> coordinates;  // signed per-coordinate errors
  std::vector<double> distances;
  for (const Observation& obs : scene.dataset.observations) {
    const int j = scene.dataset.PoseIndex(obs.pose_id);
    const auto& truth = scene.truth.poses[j].points_px;
    const auto it = truth.find(obs.camera);
    if (it == truth.end()) continue;
    for (size_t i = 0; i < obs.ids.size(); ++i)
      for (size_t t = 0; t < it->second.ids.size(); ++t)
        if (it->second.ids[t] == obs.ids[i]) {
          const Eigen::Vector2d d = obs.points_px[i] - it->second.points_px[t];
          coordinates.push_back(d.x());
          coordinates.push_back(d.y());
          distances.push_back(d.norm());
        }
  }
  DetectionError out;
  if (coordinates.empty()) return out;
  // Median absolute deviation: a few gross errors must not set the noise level.
  std::vector<double> abs_dev;
  for (double c : coordinates) abs_dev.push_back(std::abs(c));
  out.sigma_px = 1.4826 * Median(abs_dev);
  for (double d : distances) out.gross += d > 1.0 ? 1 : 0;
  out.points = static_cast<int>(distances.size());
  out.max_px = *std::max_element(distances.begin(), distances.end());
  return out;
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

bool ParseIntrinsicsOffset(const std::string& text, IntrinsicsOffset* offset) {
  const auto slash = text.find('/');
  if (slash == std::string::npos) return false;
  char* end = nullptr;
  const std::string pct = text.substr(0, slash), px = text.substr(slash + 1);
  offset->focal_percent = std::strtod(pct.c_str(), &end);
  if (pct.empty() || *end != '\0') return false;
  offset->principal_point_px = std::strtod(px.c_str(), &end);
  return !px.empty() && *end == '\0';
}

void OffsetIntrinsics(const IntrinsicsOffset& offset, Dataset* dataset) {
  for (size_t k = 0; k < dataset->cameras.size(); ++k) {
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    auto& p = dataset->cameras[k].params;
    p[0] *= 1.0 + 0.01 * offset.focal_percent * sign;
    p[1] *= 1.0 + 0.01 * offset.focal_percent * sign;
    p[2] += offset.principal_point_px * sign;
    p[3] -= offset.principal_point_px * sign;
  }
}

}  // namespace handeye::bench

namespace handeye::bench {
namespace {

double ProcessCpuSeconds() {
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec +
         1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

}  // namespace

std::vector<ImageTiming> DetectTimed(Dataset* dataset) {
  const std::unique_ptr<Detector> detector = MakeDetector(dataset->target);
  std::vector<ImageTiming> timings;
  dataset->observations.clear();
  for (const RobotPose& pose : dataset->poses) {
    for (const Camera& camera : dataset->cameras) {
      const auto image = pose.images.find(camera.name);
      if (image == pose.images.end()) continue;
      ImageTiming timing;
      timing.pose_id = pose.id;
      timing.camera = camera.name;
      const double start = ProcessCpuSeconds();
      const cv::Mat gray = LoadGrayImage(image->second, camera);
      const double loaded = ProcessCpuSeconds();
      std::optional<Detection> detection = detector->Detect(gray);
      timing.detect_cpu_s = ProcessCpuSeconds() - loaded;
      timing.load_cpu_s = loaded - start;
      timing.found = detection && !detection->ids.empty();
      if (timing.found) {
        Observation view;
        view.pose_id = pose.id;
        view.camera = camera.name;
        view.ids = std::move(detection->ids);
        view.points_px = std::move(detection->points_px);
        dataset->observations.push_back(std::move(view));
      }
      timings.push_back(std::move(timing));
    }
  }
  return timings;
}

ClassTiming SummariseTimings(const std::vector<ImageTiming>& timings, bool found) {
  std::vector<double> total_ms, load_ms;
  for (const ImageTiming& t : timings) {
    if (t.found != found) continue;
    total_ms.push_back(1000.0 * (t.load_cpu_s + t.detect_cpu_s));
    load_ms.push_back(1000.0 * t.load_cpu_s);
  }
  ClassTiming summary;
  summary.images = static_cast<int>(total_ms.size());
  if (total_ms.empty()) return summary;
  std::sort(total_ms.begin(), total_ms.end());
  summary.mean_ms = Mean(total_ms);
  summary.median_ms = Median(total_ms);
  summary.p90_ms = total_ms[static_cast<std::size_t>(0.9 * (total_ms.size() - 1))];
  summary.max_ms = total_ms.back();
  summary.mean_load_ms = Mean(load_ms);
  return summary;
}

}  // namespace handeye::bench

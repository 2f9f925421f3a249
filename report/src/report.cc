// SPDX-License-Identifier: GPL-2.0-or-later
// WriteReport(): builds the model, draws the overlays on a pool of workers
// (one image in memory per worker) while another thread draws the plots,
// then writes index.html, with the plots inline, last.
#include "handeye/report/report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "handeye/core/error.h"
#include "handeye/io/atomic_file.h"
#include "handeye/io/image.h"
#include "parallel.h"
#include "report_internal.h"

namespace handeye {
namespace {

void WriteEncoded(const std::string& path, const cv::Mat& image, const std::string& ext,
                  const std::vector<int>& params) {
  std::vector<uchar> bytes;
  if (!cv::imencode(ext, image, bytes, params)) throw InputError(path, "", "cannot encode " + ext);
  WriteFileAtomically(path, std::string(bytes.begin(), bytes.end()));
}

void MakeFolder(const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec || !std::filesystem::is_directory(folder))
    throw InputError(folder.string(), "", "cannot create the report folder: " + ec.message());
}

}  // namespace

bool ReportOptions::Check(std::string* why) const {
  auto fail = [why](const char* reason) {
    if (why) *why = reason;
    return false;
  };
  if (threads < 0) return fail("threads must be >= 0 (0 = all cores)");
  if (thumbnail_width_px < 32 || thumbnail_width_px > 4096)
    return fail("thumbnail_width_px must be in [32, 4096]");
  if (next_poses < 0 || next_poses > 20) return fail("next_poses must be in [0, 20]");
  if (!(next_goal_mm >= 0) || !std::isfinite(next_goal_mm))
    return fail("next_goal_mm must be a finite number >= 0 (0: no goal)");
  return true;
}

ReportSummary WriteReport(const Dataset& dataset, const CalibrationResult& result,
                          const std::string& dir, const ReportOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::string why;
  if (!options.Check(&why)) throw std::invalid_argument("WriteReport: " + why);
  // Overlays and residuals through the intrinsics the result used.
  Dataset solved = dataset;
  for (Camera& camera : solved.cameras)
    for (const CameraResult& cam : result.cameras)
      if (cam.name == camera.name && cam.intrinsics) {
        camera.params = cam.intrinsics->camera.params;
        camera.num_distortion = cam.intrinsics->camera.num_distortion;
        camera.has_intrinsics = true;
      }
  report::ReportModel model = report::BuildModel(solved, result, options);
  model.given_cameras = dataset.cameras;

  const std::filesystem::path root(dir);
  MakeFolder(root);
  for (const report::CameraModel& cam : model.cameras) {
    MakeFolder(root / "overlays" / cam.folder);
    MakeFolder(root / "thumbs" / cam.folder);
  }

  // No PNG parameters on purpose: OpenCV then uses its speed settings (SUB
  // filter, zlib level 1, RLE), ~1.6x faster than any explicit level (which
  // turns on libpng's adaptive filter search) for files ~40 % larger.
  const std::vector<int> png_params;
  const std::vector<int> jpeg_params = {cv::IMWRITE_JPEG_QUALITY, 85};
  // The plots (SVG for index.html) are drawn meanwhile; they only read the model.
  std::future<report::Plots> plots_drawn =
      std::async(std::launch::async, [&model] { return report::DrawPlots(model); });
  // So is the advice on what to capture next (it reads the dataset and result only).
  std::future<report::NextCapture> next_advised = std::async(
      std::launch::async, [&] { return report::AdviseNext(dataset, result, options); });
  // Overlays: each worker loads, draws and writes one view at a time.
  const std::size_t total = model.views.size();
  std::exception_ptr overlay_error;
  try {
    internal::ParallelFor(
        total, options.threads,
        [&](std::size_t i) {
          const report::ViewModel& view = model.views[i];
          const Camera& camera = *model.cameras[view.camera].camera;
          const auto& images = dataset.poses[view.pose].images;
          const auto image_path = images.find(camera.name);
          const cv::Mat gray =
              image_path == images.end() ? cv::Mat() : LoadGrayImage(image_path->second, camera);
          const cv::Mat overlay = report::DrawOverlay(model, view, gray);
          WriteEncoded((root / view.overlay_path).string(), overlay, ".png", png_params);
          cv::Mat thumb;
          const int thumb_h =
              std::max(1, static_cast<int>(std::lround(double(options.thumbnail_width_px) *
                                                       overlay.rows / overlay.cols)));
          cv::resize(overlay, thumb, cv::Size(options.thumbnail_width_px, thumb_h), 0, 0,
                     cv::INTER_AREA);
          WriteEncoded((root / view.thumb_path).string(), thumb, ".jpg", jpeg_params);
        },
        options.progress);
  } catch (...) {
    overlay_error = std::current_exception();
  }
  // Waited for in any case: the plotting thread reads the model.
  const report::Plots plots = plots_drawn.get();
  model.next = next_advised.get();
  if (overlay_error) std::rethrow_exception(overlay_error);

  ReportSummary summary;
  summary.index_html = (root / "index.html").string();
  WriteFileAtomically(summary.index_html, report::RenderHtml(model, plots, options));
  summary.overlays = static_cast<int>(total);
  summary.warnings = model.warnings;
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace handeye

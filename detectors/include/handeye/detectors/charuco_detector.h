// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// ChArUco target plugin: dictionary code books from OpenCV's aruco module
/// and the detector (OpenCV 4.6 contrib aruco, then checks and refinement).

#include <memory>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "handeye/core/charuco.h"
#include "handeye/detectors/detector.h"

namespace handeye {

/// OpenCV's predefined dictionary names (DICT_4X4_50 … DICT_APRILTAG_36h11).
std::vector<std::string> ArucoDictionaryNames();
/// The markers of a predefined dictionary as printed by cv::aruco::drawMarker.
/// Throws InputError at `/dictionary` for an unknown name, listing the known ones.
MarkerCodebook ArucoCodebook(const std::string& dictionary_name);
/// A CharucoTarget for `spec`, its dictionary resolved by name; also checks
/// the detector's options in `spec`. Throws InputError.
std::shared_ptr<const CharucoTarget> MakeCharucoTarget(const TargetSpec& spec);

/// Why a corner interpolated by OpenCV was left out (see CharucoDetector).
struct CharucoRejection {
  int corner_id = 0;
  /// "refinement" (no X junction found near it, or its squares are too
  /// foreshortened to look for one), "homography" (the two
  /// markers around it disagree with each other, or the refined corner with
  /// their local homography).
  std::string reason;
};

/// ChArUco detector (SPEC §4). Markers by cv::aruco::detectMarkers (ids not
/// on the board and ids seen twice are dropped), corners by
/// cv::aruco::interpolateCornersCharuco from the two markers touching each.
/// OpenCV 4.6 can return interpolated corners far from the true ones
/// (opencv_contrib issues 3301, 3367), so each corner is then refined to the
/// X junction of its two black squares and kept only when it agrees with the
/// local homography of its two markers' eight corners, and when those eight
/// fit one homography. Corners whose markers did not decode (the far side of
/// a board seen obliquely) are then grown from the known ones one square at
/// a time (internal::GrowCharucoCorners): predicted by the homography of the
/// known points within two squares and refined the same way; only when at
/// least three markers decoded and all of them fit one homography of the
/// board, so a misread marker numbers nothing. A view needs `min_corners` corners that are not all
/// on one line of the board; on images of 480 px and more a side, it also
/// needs a 3 x 2 block of the board's corners (a quick first stage that
/// spares images without the board OpenCV's marker search).
class CharucoDetector : public Detector {
 public:
  struct Options {
    /// Fewest corners for a view (target key `min_corners`; without the key,
    /// every corner of a board with fewer than 8, e.g. 4 for 3 x 3 squares).
    int min_corners = 8;
    /// Largest distance between a refined corner and its prediction from the
    /// local homography, as a fraction of the square's size in the image, and
    /// at least `min_homography_tolerance_px`. Marker corners are found to a
    /// fraction of a pixel; a misplaced corner is off by a marker margin or a
    /// whole square.
    double homography_tolerance = 0.1;
    double min_homography_tolerance_px = 1.0;

    bool Check(std::string* why) const;
    /// Defaults overridden by the target object's `min_corners`.
    static Options FromSpec(const TargetSpec& spec);
  };

  explicit CharucoDetector(std::shared_ptr<const CharucoTarget> target);
  CharucoDetector(std::shared_ptr<const CharucoTarget> target, const Options& options);
  ~CharucoDetector() override;

  std::optional<Detection> Detect(const cv::Mat& gray) const override;
  /// Detect(), also listing the interpolated corners that were left out.
  std::optional<Detection> Detect(const cv::Mat& gray,
                                  std::vector<CharucoRejection>* rejected) const;
  /// Detect(); a view that fails although six or more of the board's markers
  /// were decoded is checked against the other layouts a print may have (the
  /// other of OpenCV's layouts where sy is even, the squares transposed): when
  /// the markers fit one of them and not the declared one, `*mismatch` says
  /// what to change in the target.
  std::optional<Detection> DetectOrExplain(const cv::Mat& gray,
                                           std::string* mismatch) const override;

 private:
  std::optional<Detection> Find(const cv::Mat& gray, std::vector<CharucoRejection>* rejected,
                                std::string* mismatch) const;
  /// What to change in the target when markers `ids` seen at `corners` fit
  /// another layout and not the declared one; empty otherwise.
  std::string LayoutMismatch(const std::vector<int>& ids,
                             const std::vector<std::vector<cv::Point2f>>& corners) const;
  /// Corner `id` refined from `guess` (pixels) with the local homography `H`
  /// (target plane, metres, to the image), which must map `board_xy` within
  /// tolerance of `image_uv`; or why it was left out ("refinement" or
  /// "homography", CharucoRejection).
  std::variant<Eigen::Vector2d, const char*> RefineCorner(
      const cv::Mat& gray, int id, const Eigen::Matrix3d& H, const Eigen::Vector2d& guess,
      const std::vector<Eigen::Vector2d>& board_xy,
      const std::vector<Eigen::Vector2d>& image_uv) const;
  /// Drops from `found`, worst first, each corner farther from where the
  /// corners found around it put it than the homography tolerance: a
  /// corner refined to the wrong junction, whichever way it was found.
  void DropCornersOffTheirNeighbours(std::vector<std::pair<int, Eigen::Vector2d>>* found) const;
  struct OpenCvState;
  std::shared_ptr<const CharucoTarget> target_;
  Options options_;
  std::unique_ptr<const OpenCvState> cv_;
};

}  // namespace handeye

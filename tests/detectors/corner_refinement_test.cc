// SPDX-License-Identifier: GPL-2.0-or-later
// The detectors' one X-junction refiner (checkerboard and ChArUco corners):
// sub-pixel junctions of an anti-aliased X found to a few thousandths of a
// pixel, the same from precomputed gradients as from the image, and no
// corner where the gradients do not pin one down.
#include "../../detectors/src/corner_refinement.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

using namespace handeye;

namespace {

// An 8-bit image of two straight edges crossing at `centre` (pixels, centre
// of the top-left pixel at (0, 0)), along directions at `angle_a` and
// `angle_b` (radians): sectors alternately 40 and 215 grey, each pixel the
// mean of 16 × 16 samples over its area, then blurred (σ = 0.8 px). `single_edge`: the edge along
// `angle_a` only.
cv::Mat Junction(const Eigen::Vector2d& centre, double angle_a, double angle_b,
                 bool single_edge = false) {
  const Eigen::Vector2d na(-std::sin(angle_a), std::cos(angle_a)),
      nb(-std::sin(angle_b), std::cos(angle_b));
  cv::Mat image(64, 64, CV_32F);
  constexpr int kSub = 16;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      int dark = 0;
      for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
          const Eigen::Vector2d d =
              Eigen::Vector2d(x - 0.5 + (i + 0.5) / kSub, y - 0.5 + (j + 0.5) / kSub) - centre;
          dark += single_edge ? na.dot(d) > 0 : (na.dot(d) > 0) != (nb.dot(d) > 0);
        }
      image.at<float>(y, x) = static_cast<float>(215 - 175.0 * dark / (kSub * kSub));
    }
  // The lens's blur, as the renderer applies it.
  cv::GaussianBlur(image, image, cv::Size(0, 0), 0.8);
  cv::Mat gray;
  image.convertTo(gray, CV_8U);
  return gray;
}

TEST_CASE("RefineXCorner finds an X junction's sub-pixel centre", "[detectors][refine]") {
  for (const Eigen::Vector2d& centre :
       {Eigen::Vector2d(31.0, 32.0), Eigen::Vector2d(31.37, 32.81), Eigen::Vector2d(32.5, 30.5)}) {
    for (const double tilt : {0.0, 0.3, 0.6}) {
      INFO("centre " << centre.transpose() << ", tilt " << tilt);
      // Edges 90° and 50° apart (a square seen obliquely).
      for (const double between : {M_PI / 2, 50 * M_PI / 180}) {
        const cv::Mat image = Junction(centre, tilt, tilt + between);
        const Eigen::Vector2d guess = centre + Eigen::Vector2d(1.2, -0.9);
        const Eigen::Matrix2d window = 9.0 * Eigen::Matrix2d::Identity();
        const auto from_image = internal::RefineXCorner(image, guess, window, 4.0);
        REQUIRE(from_image);
        CHECK((*from_image - centre).norm() < 0.05);
        // The checkerboard path: gradients of a larger region computed once.
        const internal::Gradients gradients =
            internal::SobelGradients(image, cv::Rect(1, 1, image.cols - 2, image.rows - 2));
        const auto from_gradients = internal::RefineXCorner(gradients, guess, window, 4.0);
        REQUIRE(from_gradients);
        CHECK((*from_gradients - *from_image).norm() < 1e-9);
      }
    }
  }
}

TEST_CASE("RefineXCorner: an elliptic window and left-out pixels", "[detectors][refine]") {
  const Eigen::Vector2d centre(30.6, 33.2);
  const cv::Mat image = Junction(centre, 0.2, 0.2 + M_PI / 2);
  // A window squeezed to 3 px across one way still holds both edges.
  Eigen::Matrix2d window;
  window << 10, 0, 0, 3;
  const auto squeezed = internal::RefineXCorner(image, centre + Eigen::Vector2d(0.8, 0.5), window, 3);
  REQUIRE(squeezed);
  CHECK((*squeezed - centre).norm() < 0.05);
  // A marker's edge inside the window pulls the estimate; leaving its pixels
  // out (as the ChArUco detector does) restores it.
  cv::Mat marked = image.clone();
  // A 4 px square in one sector, clear of the board's edges by 3 px.
  const cv::Point at(static_cast<int>(centre.x()) + 4, static_cast<int>(centre.y()) + 7);
  const int inside = marked.at<std::uint8_t>(at.y + 2, at.x + 2);
  cv::rectangle(marked, cv::Rect(at, cv::Size(4, 4)), cv::Scalar(inside > 128 ? 40 : 215),
                cv::FILLED);
  const Eigen::Vector2d guess = centre + Eigen::Vector2d(0.8, 0.5);
  const Eigen::Matrix2d round = 9.0 * Eigen::Matrix2d::Identity();
  const auto pulled = internal::RefineXCorner(marked, guess, round, 3);
  const auto kept = internal::RefineXCorner(marked, guess, round, 3, [&](int x, int y) {
    return !(x >= at.x - 2 && x <= at.x + 5 && y >= at.y - 2 && y <= at.y + 5);
  });
  REQUIRE(kept);
  CHECK((*kept - centre).norm() < 0.05);
  CHECK((!pulled || (*pulled - centre).norm() > 0.1));
}

TEST_CASE("RefineXCorner finds no corner where the gradients do not fix one", "[detectors][refine]") {
  const Eigen::Vector2d centre(31.4, 32.3);
  const Eigen::Matrix2d window = 9.0 * Eigen::Matrix2d::Identity();
  // A single straight edge: the point could slide along it.
  CHECK_FALSE(internal::RefineXCorner(Junction(centre, 0.4, 0.0, true), centre, window, 4.0));
  // Flat paper.
  CHECK_FALSE(internal::RefineXCorner(cv::Mat(64, 64, CV_8U, cv::Scalar(128)), centre, window, 4.0));
  // A guess farther from the junction than it may move.
  const cv::Mat x = Junction(centre, 0.0, M_PI / 2);
  CHECK_FALSE(internal::RefineXCorner(x, centre + Eigen::Vector2d(3, 0), window, 1.0));
  CHECK(internal::RefineXCorner(x, centre + Eigen::Vector2d(3, 0), window, 4.0));
  // A window below a pixel across, a guess that is not finite, or none at all
  // in the gradients' region.
  CHECK_FALSE(internal::RefineXCorner(x, centre, 0.5 * Eigen::Matrix2d::Identity(), 4.0));
  CHECK_FALSE(internal::RefineXCorner(x, Eigen::Vector2d(std::nan(""), 3), window, 4.0));
  CHECK_FALSE(internal::RefineXCorner(internal::SobelGradients(x, cv::Rect(100, 100, 5, 5)), centre,
                                      window, 4.0));
}

}  // namespace

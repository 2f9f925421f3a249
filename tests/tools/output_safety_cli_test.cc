// SPDX-License-Identifier: GPL-2.0-or-later
// No command writes over one of its own inputs (compared by file identity:
// the same name, `dir/./x`, a hard link, a symbolic link), and every output
// location is checked before the work starts (exit 2 at once).
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "projected_cell.h"
#include "support/test_support.h"

using namespace handeye;
using Catch::Matchers::Contains;

namespace {

// Runs the command, which must refuse with exit 2 and a message naming both
// the output and the input it would have destroyed; the input is unchanged.
void RequireRefused(const std::string& args, const std::string& input,
                    const std::vector<std::string>& named) {
  const std::string before = test::ReadText(input);
  REQUIRE_FALSE(before.empty());
  std::string out;
  INFO(args);
  CHECK(test::RunHandeye(args, &out) == 2);
  INFO(out);
  for (const std::string& word : named) CHECK_THAT(out, Contains(word));
  CHECK(test::ReadText(input) == before);
}

}  // namespace

TEST_CASE("calibrate, check, export and detect refuse to write over their input",
          "[cli][overwrite]") {
  const std::string dir = test::TempDir("overwrite_cli");
  test::CalibratedSmallCell(dir);
  const std::string obs = dir + "/obs.json", result = dir + "/result.json";

  RequireRefused("calibrate " + obs + " -o " + obs, obs, {"-o names the input INPUT", obs});
  // Other names of the same file: a detour through ".", a hard link, a symbolic link.
  RequireRefused("calibrate " + obs + " -o " + dir + "/./obs.json", obs, {"INPUT"});
  REQUIRE(link(obs.c_str(), (dir + "/hard.json").c_str()) == 0);
  RequireRefused("calibrate " + obs + " -o " + dir + "/hard.json", obs, {"hard.json", "obs.json"});
  std::filesystem::create_symlink(obs, dir + "/soft.json");
  RequireRefused("calibrate " + dir + "/soft.json -o " + obs, obs, {"soft.json"});
  RequireRefused("calibrate " + obs + " -o " + dir + "/r.json --from " + result +
                     " --keep-cameras cam0 "
                     "--observations-out " +
                     result,
                 result, {"--observations-out", "--from"});
  // Two outputs that are one file, neither there yet.
  std::string out;
  CHECK(test::RunHandeye("calibrate " + obs + " -o " + dir + "/new.json --observations-out " + dir +
                             "/./new.json",
                         &out) == 2);
  CHECK_THAT(out, Contains("name the same file"));
  CHECK_FALSE(std::filesystem::exists(dir + "/new.json"));
  // The same, as a bare name and as ./name in the working folder (nothing is written there).
  const std::string bare = "same-" + std::to_string(getpid()) + ".json";
  CHECK(test::RunHandeye("calibrate " + obs + " -o " + bare + " --observations-out ./" + bare,
                         &out) == 2);
  CHECK_THAT(out, Contains("name the same file"));
  CHECK_FALSE(std::filesystem::exists(bare));

  RequireRefused("export " + result + " --to urdf -o " + result, result, {"RESULT", "-o"});
  RequireRefused("check " + result + " " + obs + " -o " + result, result, {"RESULT"});
  RequireRefused("check " + result + " " + obs + " -o " + obs, obs, {"INPUT"});
  RequireRefused("detect " + obs + " -o " + obs, obs, {"DATASET"});
  RequireRefused("report " + obs + " " + result + " -o " + dir, obs,
                 {"holds the input", "obs.json"});
  std::filesystem::create_directories(dir + "/rep");
  RequireRefused("calibrate " + obs + " -o " + dir + "/rep/r.json --report " + dir + "/rep", obs,
                 {"--report", "holds the output -o"});
}

TEST_CASE("import-poses, import-metric, target and simulate refuse to write over their input",
          "[cli][overwrite]") {
  const std::string dir = test::TempDir("overwrite_cli_import");
  nlohmann::json templ = {
      {"format", "handeye-dataset/1"},
      {"setup", "eye_to_hand"},
      {"target", {{"type", "checkerboard"}, {"inner_corners", {7, 4}}, {"square_size_m", 0.04}}},
      {"cameras",
       {{{"name", "cam0"},
         {"image_size", {640, 480}},
         {"intrinsics", {{"fx", 500.0}, {"fy", 500.0}, {"cx", 319.5}, {"cy", 239.5}}},
         {"distortion", {{"model", "none"}}}}}}};
  test::WriteText(dir + "/t.json", templ.dump());
  test::WriteText(dir + "/poses.csv", "id,x,y,z,qx,qy,qz,qw\n0001,0.4,0.1,0.9,0,0,0,1\n");
  const std::string import = "import-poses " + dir + "/poses.csv --template " + dir + "/t.json -o ";
  RequireRefused(import + dir + "/t.json", dir + "/t.json", {"--template", "t.json"});
  RequireRefused(import + dir + "/poses.csv", dir + "/poses.csv", {"POSES"});
  std::string out;
  CHECK(test::RunHandeye(import + dir + "/dataset.json", &out) == 0);

  test::WriteText(dir + "/metric/CalibrationInfo.yaml", "number_of_cameras: 1\n");
  RequireRefused("import-metric " + dir + "/metric -o " + dir + "/metric/CalibrationInfo.yaml",
                 dir + "/metric/CalibrationInfo.yaml", {"CalibrationInfo.yaml"});

  REQUIRE(test::RunHandeye("target -o " + dir + "/board.png --board 5x4 --square 0.03 --dpi 30",
                           &out) == 0);
  RequireRefused("target --target-json " + dir + "/board.json -o " + dir + "/board.png --dpi 30",
                 dir + "/board.json", {"--target-json", "board.json"});
  test::WriteText(dir + "/sim/dataset.json", test::ReadText(dir + "/board.json"));
  RequireRefused(
      "simulate " + dir + "/sim --target-json " + dir + "/sim/dataset.json --cameras 1 --poses 2",
      dir + "/sim/dataset.json", {"--target-json"});
}

TEST_CASE("outputs that cannot be written fail before the work, not after it", "[cli][overwrite]") {
  const std::string dir = test::TempDir("outputs_first_cli");
  std::string out;
  REQUIRE(test::RunHandeye("simulate " + dir +
                               "/sim --cell small --cameras 2 --poses 3 --image-size 640x360 "
                               "--seed 3 -q",
                           &out) == 0);
  const std::string dataset = dir + "/sim/dataset.json";
  // The case: the dataset's image paths lost.
  RequireRefused("detect " + dataset + " -o " + dataset, dataset, {"DATASET"});
  // A folder named as the file, a folder that takes no files (/proc), a
  // missing folder: refused before detection, which prints "target found in".
  for (const std::string& output :
       {dir, std::string("/proc/obs.json"), dir + "/missing/obs.json"}) {
    INFO(output);
    CHECK(test::RunHandeye("detect " + dataset + " -o " + output, &out) == 2);
    INFO(out);
    CHECK_THAT(out, Contains(output));
    CHECK_THAT(out, !Contains("target found in"));
  }
  CHECK(test::RunHandeye("calibrate " + dataset + " -o /proc/result.json", &out) == 2);
  CHECK_THAT(out, Contains("cannot write into folder '/proc'"));
  CHECK_THAT(out, !Contains("note:"));
  CHECK(test::RunHandeye(
            "calibrate " + dataset + " -o " + dir + "/r.json --observations-out " + dir, &out) ==
        2);
  CHECK_THAT(out, Contains("--observations-out: is a folder"));
}

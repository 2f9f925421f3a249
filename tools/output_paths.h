// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// What every subcommand checks about the files it will write before it does
/// any work: that the output can be written (its folder exists and takes a
/// new file, it is not a folder) and that it is none of the command's own
/// inputs. Files are compared by identity (device and inode), so a hard link,
/// `./x.json` against `x.json` or a symbolic link are the same file; outputs
/// that do not exist yet are compared by their canonical path.

#include <string>
#include <vector>

#include "handeye/core/dataset.h"

namespace handeye::tools {

/// A path named on the command line and the argument that named it
/// ("DATASET", "-o", "--observations-out"), for the messages.
struct NamedPath {
  std::string option;
  std::string path;
};

/// Throws InputError (exit 2) naming both paths when an output is one of the
/// inputs, when two outputs are the same file, or when an output cannot be
/// written: its folder is missing or refuses a new file, it names a folder,
/// or it exists and is not a regular file. Empty paths are skipped.
void CheckFileOutputs(const std::vector<NamedPath>& inputs, const std::vector<NamedPath>& outputs);

/// The same for an output that is a whole folder the command replaces (the
/// report): refused when an input or another output is the folder or lies
/// inside it, when it is a file, when it exists and holds something other
/// than an earlier report (`is_earlier` says whether an existing folder is
/// one), or when its parent refuses a new folder. Creates missing parent
/// folders.
void CheckFolderOutput(const std::vector<NamedPath>& inputs,
                       const std::vector<NamedPath>& other_outputs, const NamedPath& output,
                       bool (*is_earlier)(const std::string& folder));

/// The images a dataset reads, as inputs ("image").
std::vector<NamedPath> ImageInputs(const Dataset& dataset);

}  // namespace handeye::tools

// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Atomic file writes (SPEC §6: a failed run never leaves a half-written file)
/// and atomic folder replacement (the report), with the temporaries in flight
/// known, so that a program can remove them when it is interrupted.

#include <functional>
#include <string>

namespace handeye {

/// Writes `content` to a temporary file beside `path`, then renames it over
/// `path`: readers never see a half-written file. Throws InputError naming
/// the path when the folder is missing or not writable. The temporary file
/// is removed when the write fails and is a temporary in flight
/// (RemoveTemporariesInFlight) while it exists.
void WriteFileAtomically(const std::string& path, const std::string& content);

/// Builds a folder beside `dir` with `write(staging_folder)`, then puts it in
/// the place of `dir` in one step (renameat2 RENAME_EXCHANGE; where the file
/// system lacks it, two renames): a reader, or a run that is interrupted,
/// sees the whole old folder or the whole new one, never a mix; nothing of
/// the old folder is kept. When `write` throws, the staging folder is removed
/// and `dir` is left as it was. `dir`'s parent must exist.
void ReplaceFolderAtomically(const std::string& dir,
                             const std::function<void(const std::string&)>& write);

/// A new, unused name beside `path` in the same folder (so that rename() is
/// atomic): `.<name>.tmp<pid>-<random>`.
std::string TemporarySibling(const std::string& path);

/// Registers a temporary file or folder in flight for as long as it lives;
/// RemoveTemporariesInFlight() removes what is registered. It does not remove
/// the path itself when it goes out of scope.
class TemporaryInFlight {
 public:
  explicit TemporaryInFlight(std::string path);
  ~TemporaryInFlight();
  TemporaryInFlight(const TemporaryInFlight&) = delete;
  TemporaryInFlight& operator=(const TemporaryInFlight&) = delete;

 private:
  std::string path_;
};

/// Removes every temporary file and folder in flight (written by this
/// process and not yet renamed into place). For a program that is being
/// interrupted: call it from a normal thread (not from a signal handler),
/// e.g. one that waits for SIGINT/SIGTERM with sigwait.
void RemoveTemporariesInFlight();

}  // namespace handeye

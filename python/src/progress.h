// SPDX-License-Identifier: GPL-2.0-or-later
#pragma once
/// @file
/// Long work runs with the GIL released; an optional Python callable hears
/// (done, total) from the library's progress hook with the GIL taken back.

#include <pybind11/pybind11.h>

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>

namespace handeye::python {

namespace py = pybind11;

/// Wraps `callback` (None: no progress) for a library progress hook. The
/// hook may run on worker threads while the caller has released the GIL. An
/// exception the callable raises stops further calls; Rethrow() raises it
/// once the work is done (the library's loops are not interrupted midway).
class Progress {
 public:
  explicit Progress(py::object callback);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// The hook to hand to the library (empty when there is no callback).
  std::function<void(std::size_t, std::size_t)> Hook();
  /// With the GIL held: raises what the callback raised, if anything.
  void Rethrow();

 private:
  struct State;
  std::shared_ptr<State> state_;
};

/// Runs `work` with the GIL released.
template <class F>
auto WithoutGil(F&& work) {
  py::gil_scoped_release release;
  return work();
}

}  // namespace handeye::python

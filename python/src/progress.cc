// SPDX-License-Identifier: GPL-2.0-or-later
#include "progress.h"

namespace handeye::python {

struct Progress::State {
  py::object callback;  // touched only with the GIL held
  std::mutex mutex;     // the library calls one at a time; this keeps `failed` consistent anyway
  bool failed = false;
  std::optional<py::error_already_set> error;
};

Progress::Progress(py::object callback) : state_(std::make_shared<State>()) {
  if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
    throw py::type_error("progress: expected a callable taking (done, total), or None");
  state_->callback = std::move(callback);
}

Progress::~Progress() = default;

std::function<void(std::size_t, std::size_t)> Progress::Hook() {
  if (state_->callback.is_none()) return {};
  std::shared_ptr<State> state = state_;
  return [state](std::size_t done, std::size_t total) {
    std::lock_guard<std::mutex> lock(state->mutex);
    if (state->failed) return;
    py::gil_scoped_acquire gil;
    try {
      state->callback(done, total);
    } catch (py::error_already_set& e) {
      state->failed = true;
      state->error.emplace(std::move(e));
    }
  };
}

void Progress::Rethrow() {
  if (state_->error) {
    py::error_already_set error = std::move(*state_->error);
    state_->error.reset();
    throw error;
  }
}

}  // namespace handeye::python

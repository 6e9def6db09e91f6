// Writing outputs so that a reader never sees a half-written file: the
// content goes to a temporary file beside the target, which is renamed over
// the target only once complete.
#pragma once

#include <filesystem>
#include <functional>

namespace linkscape {

// Calls `write(temporary_path)`, then renames the temporary over `target`.
// If `write` throws or leaves no file, the temporary is removed, `target` is
// untouched and the exception propagates. Throws std::runtime_error when the
// target's folder does not exist or the rename fails.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write);

}  // namespace linkscape

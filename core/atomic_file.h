// Writing outputs so that a reader never sees a half-written file: the
// content goes to a temporary file beside the target, which is renamed over
// the target only once complete.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace linkscape {

// Calls `write(temporary_path)`, then puts the result at `target`:
// - a regular file (or none) at `target` is replaced by renaming the
//   temporary over it, keeping the old file's permissions;
// - a symbolic link is followed: its target is replaced, the link stays;
// - a character device or FIFO (e.g. /dev/null, a pipe) is written through,
//   never replaced;
// - a folder, block device or socket is refused before any work.
// The temporary is removed if `write` throws, writes nothing, or the process
// is interrupted by SIGINT, SIGTERM or SIGHUP. Throws std::invalid_argument
// for an empty path or a target that cannot be written to by its kind, and
// std::runtime_error naming the path and the system's reason when the
// folder is missing or not writable or the final step fails.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write);

// Writes `text` to `target` through write_atomically. Throws as it, and
// std::runtime_error naming the path when the text cannot be written.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

// Flushes standard output and throws std::runtime_error with the system's
// reason if anything written to it was lost (disk full, closed stream).
void check_stdout();

}  // namespace linkscape

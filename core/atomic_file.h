// Writing outputs so that a reader never sees a half-written file: the
// content goes to a temporary file beside the target, which is renamed over
// the target only once complete.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace linkscape {

// Calls `write(path)` with the path of a file in memory (it has no extension:
// a writer that picks its format by the name must be told it), then puts the
// result at `target`, checking every byte written to disk:
// - a regular file (or none) at `target` is replaced by renaming the
//   temporary over it, keeping the old file's permissions;
// - a symbolic link is followed: its target is replaced, the link stays;
// - a character device or FIFO (e.g. /dev/null, a pipe) is written through,
//   never replaced;
// - a folder, block device or socket is refused before any work.
// A regular file is replaced only once a complete temporary beside it is
// synced to disk: a full disk or an I/O error leaves the previous file whole.
// The temporary is removed if `write` throws, writes nothing, copying fails,
// or the process is interrupted by SIGINT, SIGTERM or SIGHUP. Throws std::invalid_argument
// for an empty path or a target that cannot be written to by its kind, and
// std::runtime_error naming the path and the system's reason when the
// folder is missing or not writable or the final step fails.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write);

// The checks write_atomically makes of `path` before any work, for a command
// to make before its work starts: std::invalid_argument where `path`, its
// links followed, is a folder, a block device or a socket; std::runtime_error
// "cannot write 'PATH': ..." where its folder is missing or not writable. A
// character device or FIFO passes (it is written through); so does an empty
// path (no such output asked for).
void check_output(const std::filesystem::path& path);

// The file `path` names once its symbolic links are followed (relative ones
// from the link's folder); a dangling link names the file it would create.
// Throws std::runtime_error for a loop of links.
std::filesystem::path followed_links(const std::filesystem::path& path);

// Writes `text` to `target` through write_atomically. Throws as it, and
// std::runtime_error naming the path when the text cannot be written.
void write_text_atomically(const std::filesystem::path& target, const std::string& text);

// Writes a set of text files so that none is replaced unless all are
// complete: every temporary is written and synced before the first rename.
// The paths are checked as write_atomically checks them, before any is written.
void write_texts_atomically(const std::vector<std::pair<std::filesystem::path, std::string>>& files);

// Flushes standard output and throws std::runtime_error with the system's
// reason if anything written to it was lost (disk full, closed stream).
void check_stdout();

}  // namespace linkscape

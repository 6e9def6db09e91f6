// Checks a command makes before any work, so that it stops at once rather
// than after minutes of computing: its outputs can be written and what it
// keeps in memory fits.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace linkscape {

// The file `path` names once its symbolic links are followed; a dangling
// link names the file it would create. Throws std::runtime_error for a
// loop of links.
std::filesystem::path followed_links(const std::filesystem::path& path);

// Refuses an output the atomic writer (core/atomic_file.h) would refuse
// once the work is done: std::invalid_argument where `path`, its links
// followed, is a folder, a block device or a socket; std::runtime_error
// "cannot write 'PATH': ..." where its folder is missing or not writable.
// A character device or FIFO passes (it is written through); so does an
// empty path (no such output asked for).
void check_output(const std::filesystem::path& path);

// The memory the system can give now (MemAvailable of /proc/meminfo), in
// bytes; nullopt where it does not say.
std::optional<double> available_memory_bytes();

}  // namespace linkscape

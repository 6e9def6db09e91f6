#include "core/preflight.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace linkscape {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void cannot_write(const fs::path& path, const std::string& why) {
  std::string message = "cannot write '";
  message += path.string();
  message += "': " + why;
  throw std::runtime_error(message);
}

}  // namespace

fs::path followed_links(const fs::path& path) {
  fs::path p = path;
  for (int hops = 0; hops < 40; ++hops) {  // the kernel's own limit (ELOOP)
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) cannot_write(path, "cannot read the symbolic link: " + ec.message());
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  cannot_write(path, "too many levels of symbolic links");
}

void check_output(const fs::path& path) {
  if (path.empty()) return;
  const fs::path file = followed_links(path);
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (fs::is_directory(status)) throw std::invalid_argument("cannot write '" + path.string() + "': it is a folder");
  if (fs::is_block_file(status) || fs::is_socket(status))
    throw std::invalid_argument("cannot write '" + path.string() +
                                "': it is a block device or socket, not a file (refused)");
  if (fs::is_character_file(status) || fs::is_fifo(status)) return;
  const fs::path folder = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, ec))
    cannot_write(path, "'" + folder.string() + (fs::exists(folder, ec) ? "' is not a folder" : "' does not exist"));
  // The writer creates a temporary beside the file and renames it over it.
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    cannot_write(path, "folder '" + folder.string() + "': " + std::strerror(errno));
}

std::optional<double> available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = 0;
  while (meminfo >> key >> kib) {
    if (key == "MemAvailable:") return kib * 1024;
    meminfo.ignore(64, '\n');
  }
  return std::nullopt;
}

}  // namespace linkscape

#include "core/atomic_file.h"

#include <unistd.h>

#include <stdexcept>
#include <string>

namespace linkscape {
namespace fs = std::filesystem;

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(folder))
    throw std::runtime_error("cannot write '" + target.string() + "': folder '" + folder.string() +
                             "' does not exist");
  // Keep the extension last: writers such as VTK's and Qt's pick the format by it.
  const fs::path temporary =
      folder / ("." + target.stem().string() + ".tmp" + std::to_string(::getpid()) + target.extension().string());
  try {
    write(temporary);
    if (!fs::exists(temporary)) throw std::runtime_error("writer produced no output");
    fs::rename(temporary, target);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
}

}  // namespace linkscape

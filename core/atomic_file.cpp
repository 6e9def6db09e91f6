#include "core/atomic_file.h"

#include <unistd.h>

#include <sstream>
#include <stdexcept>
#include <string>

namespace linkscape {
namespace fs = std::filesystem;

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(folder)) {
    std::ostringstream msg;  // (ostringstream sidesteps a GCC 12 -Wrestrict false positive)
    msg << "cannot write '" << target.string() << "': folder '" << folder.string() << "' does not exist";
    throw std::runtime_error(msg.str());
  }
  // Hidden, unique per process, extension last: VTK's and Qt's writers pick
  // the format by the extension.
  std::ostringstream name;
  name << '.' << target.stem().string() << ".tmp" << ::getpid() << target.extension().string();
  const fs::path temporary = folder / name.str();
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

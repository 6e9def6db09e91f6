#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>

namespace linkscape {
namespace fs = std::filesystem;
namespace {

// ---- Temporaries removed on SIGINT, SIGTERM and SIGHUP -------------------------
// The handler may only call async-signal-safe functions, so the live
// temporaries' names are kept in fixed buffers it can unlink directly.

constexpr int kSlots = 32;
struct Slot {
  std::atomic<bool> used{false};
  char path[4096] = {};
};
std::array<Slot, kSlots> g_slots;
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

extern "C" void remove_temporaries_and_reraise(int signal_number) {
  for (Slot& s : g_slots)
    if (s.used.load()) ::unlink(s.path);
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

void install_signal_cleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : kSignals) {
      struct sigaction previous {};
      ::sigaction(sig, nullptr, &previous);
      if (previous.sa_handler != SIG_DFL) continue;  // ignored on purpose, or someone else's handler
      struct sigaction action {};
      action.sa_handler = remove_temporaries_and_reraise;
      sigemptyset(&action.sa_mask);
      ::sigaction(sig, &action, nullptr);
    }
  });
}

// Registers a temporary for the duration of a write (no slot: the file is
// still removed on every error, only not on a signal).
class TemporaryGuard {
 public:
  explicit TemporaryGuard(const fs::path& path) : path_(path) {
    install_signal_cleanup();
    const std::string text = path.string();
    if (text.size() >= sizeof(Slot::path)) return;
    for (Slot& s : g_slots) {
      bool expected = false;
      if (s.used.compare_exchange_strong(expected, true)) {
        // A handler that runs before the name is complete unlinks a name
        // that does not exist yet: harmless.
        std::memcpy(s.path, text.c_str(), text.size() + 1);
        slot_ = &s;
        break;
      }
    }
  }
  ~TemporaryGuard() {
    std::error_code ignored;
    fs::remove(path_, ignored);
    if (slot_) {
      slot_->path[0] = '\0';
      slot_->used.store(false);
    }
  }
  TemporaryGuard(const TemporaryGuard&) = delete;
  TemporaryGuard& operator=(const TemporaryGuard&) = delete;

 private:
  fs::path path_;
  Slot* slot_ = nullptr;
};

std::string reason(int error_number) { return std::strerror(error_number); }

[[noreturn]] void fail(const fs::path& target, const std::string& why) {
  std::ostringstream msg;  // (ostringstream sidesteps a GCC 12 -Wrestrict false positive)
  msg << "cannot write '" << target.string() << "': " << why;
  throw std::runtime_error(msg.str());
}

// Follows symbolic links (relative ones from the link's folder) to the path
// that is finally written; a dangling link gives its missing target.
fs::path follow_links(const fs::path& target) {
  fs::path p = target;
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) fail(target, "cannot read the symbolic link: " + ec.message());
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  fail(target, "too many levels of symbolic links");
}

// Creates an empty temporary named after `target` in `folder` (hidden,
// unique per process, extension last: VTK's and Qt's writers pick the
// format by the extension). Fails with the system's reason.
fs::path create_temporary(const fs::path& folder, const fs::path& target, const fs::path& reported) {
  std::ostringstream name;
  name << '.' << target.stem().string() << ".tmp" << ::getpid() << target.extension().string();
  const fs::path temporary = folder / name.str();
  ::unlink(temporary.c_str());  // left by an earlier process with the same id
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) fail(reported, reason(errno));
  ::close(fd);
  return temporary;
}

void check_written(const fs::path& temporary, const fs::path& reported) {
  std::error_code ec;
  const auto size = fs::file_size(temporary, ec);
  if (ec) fail(reported, "the writer left no file (" + ec.message() + ")");
  if (size == 0) fail(reported, "the writer produced no output");
}

// Copies a finished temporary into a device or FIFO, checking every write.
void copy_into(const fs::path& temporary, const fs::path& destination, const fs::path& reported) {
  const int in = ::open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0) fail(reported, reason(errno));
  const int out = ::open(destination.c_str(), O_WRONLY | O_CLOEXEC);
  if (out < 0) {
    const int e = errno;
    ::close(in);
    fail(reported, reason(e));
  }
  char buffer[1 << 16];
  int error_number = 0;
  for (;;) {
    const ssize_t n = ::read(in, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n < 0) error_number = errno;
      break;
    }
    for (ssize_t done = 0; done < n;) {
      const ssize_t w = ::write(out, buffer + done, std::size_t(n - done));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        error_number = w < 0 ? errno : EIO;
        break;
      }
      done += w;
    }
    if (error_number) break;
  }
  ::close(in);
  if (::close(out) != 0 && !error_number) error_number = errno;
  if (error_number) fail(reported, reason(error_number));
}

}  // namespace

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  if (target.empty()) throw std::invalid_argument("the output path is empty");
  const fs::path destination = follow_links(target);
  std::error_code ec;
  const fs::file_status status = fs::status(destination, ec);
  const bool exists = fs::exists(status);
  if (exists && fs::is_directory(status))
    throw std::invalid_argument("cannot write '" + target.string() + "': it is a folder");
  const bool write_through = exists && (fs::is_character_file(status) || fs::is_fifo(status));
  if (exists && !write_through && !fs::is_regular_file(status))
    throw std::invalid_argument("cannot write '" + target.string() +
                                "': it is a block device or socket, not a file (refused)");

  if (write_through) {
    // The writer needs a real file (VTK and Qt seek); stream the finished
    // result into the device or pipe afterwards.
    const fs::path temporary = create_temporary(fs::temp_directory_path(), destination, target);
    TemporaryGuard guard(temporary);
    write(temporary);
    check_written(temporary, target);
    copy_into(temporary, destination, target);
    return;
  }

  const fs::path folder = destination.has_parent_path() ? destination.parent_path() : fs::path(".");
  if (!fs::is_directory(folder)) fail(target, "folder '" + folder.string() + "' does not exist");
  const fs::path temporary = create_temporary(folder, destination, target);
  TemporaryGuard guard(temporary);
  write(temporary);
  check_written(temporary, target);
  if (exists) {
    // Keep the permissions of the file being replaced.
    struct stat old {};
    if (::stat(destination.c_str(), &old) == 0) ::chmod(temporary.c_str(), old.st_mode & 07777);
  }
  if (::rename(temporary.c_str(), destination.c_str()) != 0) fail(target, reason(errno));
}

void write_text_atomically(const std::filesystem::path& target, const std::string& text) {
  write_atomically(target, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write '" + target.string() + "'");
  });
}

void check_stdout() {
  std::cout.flush();
  const bool stream_failed = !std::cout;
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || stream_failed) {
    const int e = errno;
    throw std::runtime_error(std::string("cannot write to standard output: ") +
                             (e ? reason(e) : "the stream is closed or full") + " (output lost)");
  }
}

}  // namespace linkscape

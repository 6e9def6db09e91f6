#include "core/atomic_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <iostream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

// A file in memory (memfd) that writers fill through an ordinary path. Most
// writers (VTK's, Qt's, OpenMesh's) do not report a short write, so they never
// write to disk themselves: a write to memory cannot run out of disk space,
// and the bytes go to disk afterwards through copy_all, which checks them.
class MemoryFile {
 public:
  explicit MemoryFile(const fs::path& reported) : fd_(::memfd_create("linkscape-output", MFD_CLOEXEC)) {
    if (fd_ < 0) fail(reported, "cannot create the file in memory: " + reason(errno));
  }
  ~MemoryFile() { ::close(fd_); }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  int fd() const { return fd_; }
  // The path a writer opens (it has no extension: writers are told the format).
  fs::path path() const { return "/proc/self/fd/" + std::to_string(fd_); }
  off_t size() const {
    struct stat s {};
    return ::fstat(fd_, &s) == 0 ? s.st_size : 0;
  }

 private:
  int fd_;
};

// Copies the whole of `in` into `out`, checking every write; returns 0 or
// the errno of the first failure.
int copy_all(int in, int out) {
  char buffer[1 << 16];
  for (off_t offset = 0;;) {
    const ssize_t n = ::pread(in, buffer, sizeof buffer, offset);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return 0;
    offset += n;
    for (ssize_t done = 0; done < n;) {
      const ssize_t w = ::write(out, buffer + done, std::size_t(n - done));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) return w < 0 ? errno : EIO;
      done += w;
    }
  }
}

// What is at an output path, checked as the writer will need it: a regular
// file (or none) in an existing folder, or a character device or FIFO to
// write through. Throws as check_output says.
struct Target {
  fs::path path;  // symbolic links followed
  bool exists = false;
  bool write_through = false;
};

Target check_target(const fs::path& target) {
  if (target.empty()) throw std::invalid_argument("the output path is empty");
  if (!target.has_filename())
    throw std::invalid_argument("cannot write '" + target.string() + "': it names a folder (it ends in '/'), not a file");
  Target t{followed_links(target)};
  std::error_code ec;
  const fs::file_status status = fs::status(t.path, ec);
  t.exists = fs::exists(status);
  if (t.exists && fs::is_directory(status))
    throw std::invalid_argument("cannot write '" + target.string() + "': it is a folder");
  t.write_through = t.exists && (fs::is_character_file(status) || fs::is_fifo(status));
  if (t.exists && !t.write_through && !fs::is_regular_file(status))
    throw std::invalid_argument("cannot write '" + target.string() +
                                "': it is a block device or socket, not a file (refused)");
  if (t.write_through) return t;
  const fs::path folder = t.path.has_parent_path() ? t.path.parent_path() : fs::path(".");
  const fs::file_status folder_status = fs::status(folder, ec);
  if (!fs::exists(folder_status)) fail(target, "folder '" + folder.string() + "' does not exist");
  if (!fs::is_directory(folder_status)) fail(target, "'" + folder.string() + "' is not a folder");
  // The temporary is created beside the file and renamed over it.
  if (::access(folder.c_str(), W_OK | X_OK) != 0) fail(target, "folder '" + folder.string() + "': " + reason(errno));
  return t;
}

// One output, from the check of its path to its commit. A regular file (or
// none) is replaced by renaming a temporary over it; the temporary is created
// before any work, so an unwritable place is refused at once. A character
// device or FIFO is written through, only once everything is ready.
class Output {
 public:
  explicit Output(const fs::path& target) : reported_(target) {
    const Target t = check_target(target);
    path_ = t.path;
    exists_ = t.exists;
    write_through_ = t.write_through;
    if (write_through_) return;
    std::ostringstream name;  // hidden, unique per process
    name << '.' << path_.stem().string() << ".tmp" << ::getpid() << path_.extension().string();
    temporary_ = folder() / name.str();
    ::unlink(temporary_.c_str());  // left by an earlier process with the same id
    fd_ = ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0) fail(target, reason(errno));
    guard_ = std::make_unique<TemporaryGuard>(temporary_);
  }
  ~Output() {
    if (fd_ >= 0) ::close(fd_);
  }
  Output(Output&& other) noexcept
      : reported_(std::move(other.reported_)), path_(std::move(other.path_)), exists_(other.exists_),
        write_through_(other.write_through_), temporary_(std::move(other.temporary_)), fd_(other.fd_),
        guard_(std::move(other.guard_)), content_(std::move(other.content_)) {
    other.fd_ = -1;
  }
  Output(const Output&) = delete;
  Output& operator=(const Output&) = delete;
  Output& operator=(Output&&) = delete;

  // Runs the writer into memory, then (for a file) copies the result into
  // the temporary and syncs it: a full disk or an I/O error shows here.
  void fill(const std::function<void(const fs::path&)>& write) {
    content_ = std::make_unique<MemoryFile>(reported_);
    write(content_->path());
    if (content_->size() == 0) fail(reported_, "the writer produced no output");
    if (write_through_) return;
    int error_number = copy_all(content_->fd(), fd_);
    if (!error_number && ::fsync(fd_) != 0) error_number = errno;  // a late ENOSPC or EIO shows here
    if (::close(fd_) != 0 && !error_number) error_number = errno;
    fd_ = -1;
    content_.reset();
    if (error_number) fail(reported_, reason(error_number));
  }

  void commit() {
    if (write_through_) {
      const int out = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
      if (out < 0) fail(reported_, reason(errno));
      int error_number = copy_all(content_->fd(), out);
      if (::close(out) != 0 && !error_number) error_number = errno;
      if (error_number) fail(reported_, reason(error_number));
      return;
    }
    if (exists_) {
      // Keep the permissions of the file being replaced.
      struct stat old {};
      if (::stat(path_.c_str(), &old) == 0) ::chmod(temporary_.c_str(), old.st_mode & 07777);
    }
    if (::rename(temporary_.c_str(), path_.c_str()) != 0) fail(reported_, reason(errno));
    // Make the rename itself durable (best effort: the file is already in place).
    const int dir = ::open(folder().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
      ::fsync(dir);
      ::close(dir);
    }
  }

 private:
  fs::path folder() const { return path_.has_parent_path() ? path_.parent_path() : fs::path("."); }

  fs::path reported_;  // the path as the user gave it
  fs::path path_;      // symbolic links followed
  bool exists_ = false;
  bool write_through_ = false;
  fs::path temporary_;
  int fd_ = -1;                            // the temporary, open until filled
  std::unique_ptr<TemporaryGuard> guard_;  // removes the temporary unless it was renamed
  std::unique_ptr<MemoryFile> content_;    // what a device or FIFO gets at commit
};

void write_text_to(const fs::path& path, const std::string& text, const fs::path& reported) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) fail(reported, "the text could not be written to memory");
}

}  // namespace

fs::path followed_links(const fs::path& path) {
  fs::path p = path;
  for (int hops = 0; hops < 40; ++hops) {  // the kernel's own limit (ELOOP)
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) fail(path, "cannot read the symbolic link: " + ec.message());
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  fail(path, "too many levels of symbolic links");
}

void check_output(const fs::path& path) {
  if (!path.empty()) check_target(path);
}

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  Output output(target);
  output.fill(write);
  output.commit();
}

void write_text_atomically(const fs::path& target, const std::string& text) {
  write_atomically(target, [&](const fs::path& path) { write_text_to(path, text, target); });
}

void write_texts_atomically(const std::vector<std::pair<fs::path, std::string>>& files) {
  std::vector<Output> outputs;
  outputs.reserve(files.size());
  for (const auto& file : files) outputs.emplace_back(file.first);
  for (std::size_t i = 0; i < files.size(); ++i)
    outputs[i].fill([&](const fs::path& path) { write_text_to(path, files[i].second, files[i].first); });
  for (Output& output : outputs) output.commit();
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

// A small file system to fill, for the tests of outputs on a full disk: a
// tmpfs mounted on a fresh folder (mounting needs root, as CI runs; elsewhere
// the tests that use it are skipped and say why), unmounted at the end.
#pragma once

#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

class FullDisk {
 public:
  explicit FullDisk(const std::string& name) {
    folder_ = std::filesystem::temp_directory_path() / ("linkscape_full_disk_" + name + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_);
    if (::mount("tmpfs", folder_.c_str(), "tmpfs", 0, "size=512k") != 0)
      why_not_ = std::string("cannot mount a tmpfs: ") + std::strerror(errno) + " (the full-disk tests need root)";
  }
  ~FullDisk() {
    if (why_not_.empty()) ::umount2(folder_.c_str(), MNT_DETACH);
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }
  FullDisk(const FullDisk&) = delete;
  FullDisk& operator=(const FullDisk&) = delete;

  // Empty when the disk is mounted, else why it is not.
  const std::string& why_not() const { return why_not_; }
  const std::filesystem::path& folder() const { return folder_; }

  // Fills every byte left with one file, `filler`, then frees `leave` bytes.
  void fill(std::uintmax_t leave = 0) const {
    const std::filesystem::path filler = folder_ / "filler";
    FILE* f = std::fopen(filler.c_str(), "wb");
    const std::vector<char> block(4096, 'x');
    while (std::fwrite(block.data(), 1, block.size(), f) == block.size() && std::fflush(f) == 0) {
    }
    std::fclose(f);
    const std::uintmax_t size = std::filesystem::file_size(filler);
    std::filesystem::resize_file(filler, size > leave ? size - leave : 0);
  }

 private:
  std::filesystem::path folder_;
  std::string why_not_;
};

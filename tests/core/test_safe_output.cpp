// Outputs never damage what is at the output path: devices and pipes are
// written through, links followed, folders refused, temporaries removed on
// errors and on signals.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <thread>

#include "core/atomic_file.h"
#include "full_disk.h"

using namespace linkscape;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("linkscape_safe_output_" + name + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  write_atomically(p, [&](const fs::path& tmp) { std::ofstream(tmp) << text; });
}

// Files in `dir` other than `keep` (a leftover temporary shows up here).
int other_files(const fs::path& dir, const std::set<std::string>& keep) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    if (!keep.count(e.path().filename().string())) ++n;
  return n;
}

}  // namespace

TEST(SafeOutput, ReplacesARegularFileAndKeepsItsPermissions) {
  const fs::path dir = fresh_dir("regular");
  const fs::path file = dir / "out.csv";
  std::ofstream(file) << "old";
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write_text(file, "new");
  EXPECT_EQ(read_all(file), "new");
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(other_files(dir, {"out.csv"}), 0);
}

TEST(SafeOutput, FollowsASymbolicLinkAndKeepsIt) {
  const fs::path dir = fresh_dir("link");
  std::ofstream(dir / "real.csv") << "old";
  fs::create_symlink("real.csv", dir / "link.csv");  // relative, as users make them
  write_text(dir / "link.csv", "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.csv")));
  EXPECT_EQ(read_all(dir / "real.csv"), "new");
  EXPECT_EQ(other_files(dir, {"real.csv", "link.csv"}), 0);
}

TEST(SafeOutput, WritesThroughAFifoWithoutReplacingIt) {
  const fs::path dir = fresh_dir("fifo");
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string received;
  std::thread reader([&] { received = read_all(fifo); });
  write_text(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(received, "through the pipe");
  EXPECT_TRUE(fs::is_fifo(fs::status(fifo)));
}

TEST(SafeOutput, WritesThroughACharacterDeviceWithoutReplacingIt) {
  // A private copy of /dev/null (major 1, minor 3), so that a regression
  // could only ever replace this node, never the system's.
  const fs::path dir = fresh_dir("device");
  const fs::path node = dir / "null";
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) GTEST_SKIP() << "mknod needs root";
  write_text(node, "discarded");
  EXPECT_TRUE(fs::is_character_file(fs::status(node)));
  EXPECT_EQ(other_files(dir, {"null"}), 0);
}

TEST(SafeOutput, RefusesFoldersAndEmptyPaths) {
  const fs::path dir = fresh_dir("folder");
  fs::create_directories(dir / "sub");
  bool called = false;
  EXPECT_THROW(write_atomically(dir / "sub", [&](const fs::path&) { called = true; }), std::invalid_argument);
  EXPECT_THROW(write_atomically("", [&](const fs::path&) { called = true; }), std::invalid_argument);
  // A path ending in '/' names a folder, whether or not one is there.
  for (const fs::path& p : {dir / "sub/", dir / "missing.csv/"}) {
    try {
      write_atomically(p, [&](const fs::path&) { called = true; });
      ADD_FAILURE() << "expected an error for " << p;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("names a folder"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(called);  // refused before any work
}

TEST(SafeOutput, NamesThePathAndTheReasonWhenTheFolderIsMissingOrUnwritable) {
  try {
    write_text("/nonexistent-folder-for-linkscape/out.csv", "x");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-folder-for-linkscape/out.csv"), std::string::npos) << e.what();
  }
  // /proc refuses new files even to root: the system's reason is given.
  try {
    write_text("/proc/linkscape-out.csv", "x");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'/proc/linkscape-out.csv': "), std::string::npos) << what;
    EXPECT_GT(what.size(), std::string("cannot write '/proc/linkscape-out.csv': ").size()) << what;
  }
}

TEST(SafeOutput, AWriterThatFailsOrWritesNothingLeavesTheOldFileAndNoTemporary) {
  const fs::path dir = fresh_dir("fail");
  const fs::path file = dir / "out.vti";
  std::ofstream(file) << "old";
  EXPECT_THROW(write_atomically(file,
                                [](const fs::path& tmp) {
                                  std::ofstream(tmp) << "partial";
                                  throw std::runtime_error("writer failed");
                                }),
               std::runtime_error);
  EXPECT_THROW(write_atomically(file, [](const fs::path&) {}), std::runtime_error);  // wrote nothing
  EXPECT_EQ(read_all(file), "old");
  EXPECT_EQ(other_files(dir, {"out.vti"}), 0);
}

TEST(SafeOutput, ASignalDuringTheWriteRemovesTheTemporary) {
  for (int sig : {SIGTERM, SIGINT, SIGHUP}) {
    const fs::path dir = fresh_dir("signal" + std::to_string(sig));
    const fs::path file = dir / "out.vti";
    std::ofstream(file) << "old";
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      write_atomically(file, [&](const fs::path& tmp) {
        std::ofstream(tmp) << "half of a large file";
        std::raise(sig);  // as if the user pressed Ctrl-C now
      });
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "signal " << sig;
    EXPECT_EQ(read_all(file), "old");
    EXPECT_EQ(other_files(dir, {"out.vti"}), 0) << "a temporary was left behind after signal " << sig;
  }
}

// Writers such as VTK's, Qt's and OpenMesh's do not report a short write; on
// a full disk their output used to be truncated and put in place as if whole.
TEST(SafeOutput, AFullDiskLeavesThePreviousFileWholeAndNoTemporary) {
  FullDisk disk("writer");
  if (!disk.why_not().empty()) GTEST_SKIP() << disk.why_not();
  const fs::path file = disk.folder() / "mesh.ply";
  std::ofstream(file) << "old";
  disk.fill();
  const std::string large(1 << 20, 'm');
  try {
    // Like those writers: nothing checked.
    write_atomically(file, [&](const fs::path& tmp) { std::ofstream(tmp) << large; });
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write '" + file.string() + "': No space left on device"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_all(file), "old");
  EXPECT_EQ(other_files(disk.folder(), {"mesh.ply", "filler"}), 0);
}

TEST(SafeOutput, AFullDeviceIsAnErrorNotASilentLoss) {
  try {
    write_text_atomically("/dev/full", "anything");
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
}

// Writing through a pipe needs no temporary file: a full TMPDIR is no reason
// to lose or cut the output.
TEST(SafeOutput, APipeIsWrittenWholeWhenTheTemporaryFolderIsFull) {
  FullDisk disk("tmpdir");
  if (!disk.why_not().empty()) GTEST_SKIP() << disk.why_not();
  disk.fill();
  const fs::path dir = fresh_dir("fifo_full_tmp");
  const fs::path fifo = dir / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string text(300000, 'p');
  std::string received;
  std::thread reader([&] { received = read_all(fifo); });
  const char* old_tmpdir = std::getenv("TMPDIR");
  const std::string saved = old_tmpdir ? old_tmpdir : "";
  ::setenv("TMPDIR", disk.folder().c_str(), 1);
  EXPECT_NO_THROW(write_text_atomically(fifo, text));
  if (old_tmpdir) ::setenv("TMPDIR", saved.c_str(), 1);
  else ::unsetenv("TMPDIR");
  reader.join();
  EXPECT_EQ(received.size(), text.size());
}

// A set of outputs (bench's three tables) is replaced together or not at all.
TEST(SafeOutput, ASetOfFilesIsReplacedWhollyOrNotAtAll) {
  FullDisk disk("set");
  if (!disk.why_not().empty()) GTEST_SKIP() << disk.why_not();
  const fs::path a = disk.folder() / "bench.csv", b = disk.folder() / "bench.methods.csv";
  std::ofstream(a) << "old a";
  std::ofstream(b) << "old b";
  disk.fill(64 * 1024);  // room for a small table, not for a large one
  EXPECT_THROW(write_texts_atomically({{a, "new a"}, {b, std::string(1 << 20, 'b')}}), std::runtime_error);
  EXPECT_EQ(read_all(a), "old a");
  EXPECT_EQ(read_all(b), "old b");
  EXPECT_EQ(other_files(disk.folder(), {"bench.csv", "bench.methods.csv", "filler"}), 0);

  const fs::path dir = fresh_dir("set_ok");
  write_texts_atomically({{dir / "x.csv", "x"}, {dir / "y.csv", "y"}});
  EXPECT_EQ(read_all(dir / "x.csv"), "x");
  EXPECT_EQ(read_all(dir / "y.csv"), "y");
  // A path that cannot be written is refused before anything is written.
  EXPECT_THROW(write_texts_atomically({{dir / "x.csv", "new"}, {dir / "missing" / "y.csv", "y"}}), std::runtime_error);
  EXPECT_EQ(read_all(dir / "x.csv"), "x");
}

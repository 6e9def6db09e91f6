// What a headless command says on the terminal: a progress line with the
// time left while long work runs (only on an interactive stderr), a
// one-line summary when it succeeds, and the name a mistyped word was
// probably meant to be. --quiet silences the progress and the summary.
#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace linkscape::gui {

// "sampling 42 %, 3.1 s left", or "writing f.vti, 1.2 s" for a step that
// reports no fraction (time spent so far). No estimate before the step
// has run a moment and done a little, where it would only be noise.
std::string progress_text(const std::string& step, std::optional<double> fraction, double seconds);

// One line on stderr, redrawn in place four times a second while a step
// runs, cleared when the next step starts and on destruction. Silent
// (every call a no-op) when quiet or when stderr is not a terminal.
class ProgressLine {
 public:
  explicit ProgressLine(bool quiet);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  void step(const std::string& name);  // starts a step (fraction unknown)
  void report(double fraction);        // the step's progress, 0..1; any thread
  void clear();                        // ends the step and clears the line
  bool shown() const { return shown_; }

 private:
  void draw();  // with mutex_ held
  bool shown_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::string step_;
  std::optional<double> fraction_;
  std::chrono::steady_clock::time_point start_;
  std::size_t width_ = 0;  // of the line on screen, to clear it
  std::thread ticker_;
};

// "linkscape: <text>" on stderr unless quiet.
void summary(bool quiet, const std::string& text);

// Seconds since `start`, as "0.21 s".
std::string seconds_since(std::chrono::steady_clock::time_point start);

// The candidate `word` was most likely meant to be (edit distance with
// transpositions at most a third of its length, at least 1), if any.
std::optional<std::string> closest_name(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace linkscape::gui

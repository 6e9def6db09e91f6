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
// `first` is the fraction the step started from (resumed work).
std::string progress_text(const std::string& step, std::optional<double> fraction, double seconds,
                          double first = 0);

// One line on stderr, redrawn in place four times a second while a step
// runs, cleared when the next step starts and on destruction. When stderr
// is not a terminal (a log file of a batch job), a plain line every 10 s
// once a step has run that long. Silent (every call a no-op) when quiet.
// The time left counts from the step's first reported fraction, so a run
// resumed half-way does not look twice as fast.
class ProgressLine {
 public:
  explicit ProgressLine(bool quiet);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  void step(const std::string& name);      // starts a step (fraction unknown)
  void describe(const std::string& text);  // the same step, new words ("12 designs evaluated"); any thread
  void report(double fraction);            // the step's progress, 0..1; any thread
  void clear();                            // ends the step and clears the line
  bool shown() const { return shown_ || logged_; }

 private:
  void draw();  // with mutex_ held
  void log();   // with mutex_ held: a plain line, at most every 10 s
  bool shown_;   // redrawn in place on a terminal
  bool logged_;  // plain lines into a file
  std::optional<double> first_fraction_;
  std::chrono::steady_clock::time_point logged_at_;
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

// The width text is wrapped to: the terminal's where standard output is one,
// else $COLUMNS, else 80 (pipes, help2man's man page); within 40..250.
std::size_t terminal_width();

// `text` with its lines broken at spaces to at most `width` characters
// (a word longer than that stands alone); its own line breaks are kept.
std::string wrap_text(const std::string& text, std::size_t width);

// "4.2 s", "35 s", "2 min 5 s": a duration for people.
std::string duration_text(double seconds);

// Seconds since `start`, as "0.21 s".
std::string seconds_since(std::chrono::steady_clock::time_point start);

}  // namespace linkscape::gui

#include "gui/cli/terminal.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <cstdlib>
#include <sstream>

#include "core/csv.h"

namespace linkscape::gui {

std::string duration_text(double s) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  if (s < 10) out.precision(1);
  else out.precision(0);
  if (s < 120) out << s << " s";
  else out << int(s / 60) << " min " << int(std::fmod(s, 60.0)) << " s";
  return out.str();
}

std::string progress_text(const std::string& step, std::optional<double> fraction, double seconds, double first) {
  if (!fraction) return step + ", " + duration_text(seconds);
  const double f = std::clamp(*fraction, 0.0, 1.0), done = f - std::clamp(first, 0.0, f);
  std::string text = step + " " + std::to_string(int(f * 100)) + " %";
  if (seconds >= 0.5 && done >= 0.02 && f < 1) text += ", " + duration_text(seconds * (1 - f) / done) + " left";
  return text;
}

ProgressLine::ProgressLine(bool quiet)
    : shown_(!quiet && ::isatty(STDERR_FILENO)), logged_(!quiet && !::isatty(STDERR_FILENO)) {
  if (!shown_) return;
  ticker_ = std::thread([this] {
    std::unique_lock lock(mutex_);
    while (!stop_) {
      if (!step_.empty()) draw();
      wake_.wait_for(lock, std::chrono::milliseconds(250));
    }
  });
}

ProgressLine::~ProgressLine() {
  if (!shown_) return;
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  ticker_.join();
  clear();
}

void ProgressLine::step(const std::string& name) {
  if (!shown()) return;
  std::lock_guard lock(mutex_);
  step_ = name;
  fraction_.reset();
  first_fraction_.reset();
  start_ = logged_at_ = std::chrono::steady_clock::now();
  if (shown_) draw();
}

void ProgressLine::describe(const std::string& text) {
  if (!shown()) return;
  std::lock_guard lock(mutex_);
  step_ = text;
  if (logged_) log();
}

void ProgressLine::report(double fraction) {
  if (!shown()) return;
  std::lock_guard lock(mutex_);
  if (!first_fraction_) first_fraction_ = fraction;
  fraction_ = fraction;
  if (logged_) log();
}

void ProgressLine::log() {
  const auto now = std::chrono::steady_clock::now();
  if (now - logged_at_ < std::chrono::seconds(10)) return;
  logged_at_ = now;
  std::cerr << progress_text(step_, fraction_, std::chrono::duration<double>(now - start_).count(),
                             first_fraction_.value_or(0))
            << std::endl;
}

void ProgressLine::clear() {
  if (!shown_) return;
  std::lock_guard lock(mutex_);
  if (width_ > 0) std::cerr << "\r" << std::string(width_, ' ') << "\r" << std::flush;
  width_ = 0;
  step_.clear();
}

void ProgressLine::draw() {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string text = progress_text(step_, fraction_, seconds, first_fraction_.value_or(0));
  // Pad over the previous line's tail.
  std::cerr << "\r" << text << std::string(width_ > text.size() ? width_ - text.size() : 0, ' ') << std::flush;
  width_ = std::max(width_, text.size());
}

void summary(bool quiet, const std::string& text) {
  if (!quiet) std::cerr << "linkscape: " << text << "\n";
}

std::string seconds_since(std::chrono::steady_clock::time_point start) {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(s < 10 ? 2 : 1);
  out << s << " s";
  return out.str();
}

std::size_t terminal_width() {
  std::size_t width = 80;
  winsize size{};
  if (::isatty(STDOUT_FILENO) && ::ioctl(STDOUT_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) {
    width = size.ws_col;
  } else if (const char* columns = std::getenv("COLUMNS")) {
    if (const std::optional<double> n = parse_number(columns); n && *n >= 1 && *n <= 10000) width = std::size_t(*n);
  }
  return std::clamp<std::size_t>(width, 40, 250);
}

std::string wrap_text(const std::string& text, std::size_t width) {
  std::string out, line;
  std::istringstream paragraphs(text);
  for (std::string paragraph; std::getline(paragraphs, paragraph);) {
    // An indented paragraph keeps its indentation, and its continuation
    // lines hang two columns further in (an example's command line).
    const std::size_t first = std::min(paragraph.find_first_not_of(' '), paragraph.size());
    const std::string indent(first, ' '), hanging = first == 0 ? indent : indent + "  ";
    std::istringstream words(paragraph);
    line.clear();
    bool first_line = true;
    for (std::string word; words >> word;) {
      if (!line.empty() && line.size() + 1 + word.size() > width) {
        out += line + '\n';
        line.clear();
        first_line = false;
      }
      line += (line.empty() ? (first_line ? indent : hanging) : " ") + word;
    }
    out += line + '\n';
  }
  if (!text.empty() && text.back() != '\n' && !out.empty()) out.pop_back();
  return out;
}

}  // namespace linkscape::gui

// The progress line's words, without timing anything: progress_text is a
// pure function.
#include <gtest/gtest.h>

#include "gui/cli/terminal.h"

using linkscape::gui::progress_text;

TEST(TerminalProgress, TheTimeLeftFollowsTheShareDone) {
  // 40 % in 2 s: 3 s to go.
  EXPECT_EQ(progress_text("sampling", 0.4, 2.0), "sampling 40 %, 3.0 s left");
  // Too early to tell (under half a second, or under 2 % done): no estimate.
  EXPECT_EQ(progress_text("sampling", 0.4, 0.3), "sampling 40 %");
  EXPECT_EQ(progress_text("sampling", 0.01, 5.0), "sampling 1 %");
  // A step resumed at 50 %: 60 % after 1 s means 10 % a second, 4 s to go.
  EXPECT_EQ(progress_text("sweep", 0.6, 1.0, 0.5), "sweep 60 %, 4.0 s left");
  // Without a share, the time spent.
  EXPECT_EQ(progress_text("writing f.vti", std::nullopt, 1.25), "writing f.vti, 1.2 s");
  EXPECT_EQ(progress_text("fit", std::nullopt, 150), "fit, 2 min 30 s");
}

TEST(TerminalText, WrapsAtSpacesAndKeepsLineBreaks) {
  using linkscape::gui::wrap_text;
  EXPECT_EQ(wrap_text("one two three four", 9), "one two\nthree\nfour");
  EXPECT_EQ(wrap_text("a\nb c", 80), "a\nb c");
  EXPECT_EQ(wrap_text("averyveryverylongword x", 5), "averyveryverylongword\nx");  // a long word stands alone
  EXPECT_EQ(wrap_text("", 10), "");
  // An indented line keeps its indentation; its continuation hangs two further in.
  EXPECT_EQ(wrap_text("  cmd one two\n      what it does", 12), "  cmd one\n    two\n      what\n        it\n        does");
  EXPECT_EQ(wrap_text("ends in a break\n", 80), "ends in a break\n");
}

#!/usr/bin/env bash
# Usage: packaging/check-headless.sh LINKSCAPE_BINARY
#
# Checks a build configured with -DLINKSCAPE_WINDOW=OFF (the command line
# alone, for cluster nodes): the binary loads no Qt Widgets, Charts or
# OpenGL library (ldd, the libraries it needs directly and through others),
# refuses to open a window with exit 1, saying the build has none, and runs
# a command. Prints one PASS/FAIL line per check and the Qt libraries it
# does load; exits non-zero if any check failed.
set -uo pipefail
[ $# -eq 1 ] && [ -x "$1" ] || { echo "usage: $0 LINKSCAPE_BINARY" >&2; exit 2; }
exe=$1
failures=0
pass() { echo "PASS: $*"; }
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

libraries=$(ldd "$exe") || { echo "FAIL: ldd $exe"; exit 1; }
window_libraries=$(grep -E 'libQt6(Widgets|Charts|OpenGL)' <<<"$libraries")
if [ -z "$window_libraries" ]; then
  pass "ldd: no Qt6Widgets, Qt6Charts or Qt6OpenGL"
else
  fail "ldd: the binary loads window libraries:"$'\n'"$window_libraries"
fi
echo "Qt libraries loaded: $(grep -oE 'libQt6[A-Za-z]+' <<<"$libraries" | sort -u | tr '\n' ' ')"

# A binary with the window would open it here: asked only of one without.
if [ $failures -eq 0 ]; then
  out=$(QT_QPA_PLATFORM=offscreen "$exe" 2>&1); code=$?
  if [ $code -eq 1 ] && grep -q 'this build has no window' <<<"$out"; then
    pass "without a command: exit 1, 'this build has no window'"
  else
    fail "without a command: exit $code, output: $out"
  fi
fi

if printf 'alpha,beta,gamma\n0.1,0.2,0.3\n' | "$exe" eval --mechanism parallel-12r --fk - | grep -q '^alpha'; then
  pass "eval --fk runs"
else
  fail "eval --fk"
fi
exit $((failures > 0))

#!/usr/bin/env bash
# Usage: packaging/make-manpage.sh LINKSCAPE_BINARY OUTPUT.1.gz
#
# Writes the manual page from the program's own help texts (the top-level
# --help and every command's --help), so the two never disagree. The page
# carries no date, and gzip -n no timestamp: the same binary gives the
# same bytes.
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 LINKSCAPE_BINARY OUTPUT.1.gz" >&2; exit 2; }
exe=$1 out=$2
export QT_QPA_PLATFORM=offscreen
# The page indents its text by 7 columns: help wrapped to 72 keeps it within 80.
export COLUMNS=72

# Help text as preformatted roff: backslashes escaped, control characters
# at a line start neutralised.
roff() { sed -e 's/\\/\\e/g' -e "s/^\([.']\)/\\\\\&\1/"; }

version=$("$exe" --version | awk '{print $2}')
# The whole help first: awk stopping early must not break the pipe under pipefail.
help=$("$exe" --help)
commands=$(awk '/^Subcommands:/ {on = 1; next} on && /^  [a-z]/ {print $1} on && /^$/ {exit}' <<<"$help")

tmp=$(mktemp "${out}.XXXXXX")
trap 'rm -f "$tmp"' EXIT
{
  echo ".TH LINKSCAPE 1 \"\" \"linkscape $version\" \"User Commands\""
  echo ".SH NAME"
  echo "linkscape \\- kinematic design of parallel haptic-device mechanisms"
  echo ".SH SYNOPSIS"
  echo ".B linkscape"
  echo "[\\fIOPTIONS\\fR] [\\fIFILE\\fR]"
  echo ".br"
  echo ".B linkscape"
  echo "\\fICOMMAND\\fR [\\fIOPTIONS\\fR]"
  echo ".SH DESCRIPTION"
  echo "Without a command, linkscape opens its window on a mechanism preset, or on"
  echo "\\fIFILE\\fR, a saved session or a preset. With a command it runs headless."
  echo ".PP"
  echo ".nf"
  awk '/^Examples/ {exit} {print}' <<<"$help" | roff
  echo ".fi"
  echo ".SH COMMANDS"
  for c in $commands; do
    echo ".SS $c"
    echo ".nf"
    "$exe" "$c" --help | roff
    echo ".fi"
  done
  echo ".SH EXAMPLES"
  echo ".nf"
  awk '/^Examples/ {on = 1; next} on && /^$/ {exit} on {print}' <<<"$help" | roff
  echo ".fi"
  echo ".SH WINDOW"
  echo "The window's keyboard shortcuts (Help > Keyboard shortcuts lists the same):"
  echo ".PP"
  echo ".nf"
  { "$exe" --shortcuts 2>/dev/null || echo "(this build has no window)"; } | roff
  echo ".fi"
  echo ".SH ENVIRONMENT"
  echo ".TP"
  echo ".B LINKSCAPE_SIMD_TARGET"
  echo "Use at most this SIMD instruction set in the field kernels (e.g. AVX2, SSE4, baseline)."
  echo ".TP"
  echo ".B LINKSCAPE_FIELD_KERNEL"
  echo "The parallel-12r planar field kernel: scalar, vector or vector-mirrored (the default)."
  echo ".TP"
  echo ".B LINKSCAPE_ASSETS"
  echo "A folder with mechanisms/*.json presets, searched before the installed ones."
  echo ".SH FILES"
  echo ".TP"
  echo ".I /usr/share/linkscape/mechanisms/*.json"
  echo "The shipped mechanism presets."
  echo ".TP"
  echo ".I /usr/share/doc/linkscape/"
  echo "The user guide (Markdown), which Help > Documentation (F1) shows in the window."
  echo ".SH EXIT STATUS"
  echo "0 on success, 2 for bad input or usage (the message names the file, line or option),"
  echo "1 for any other failure. \\fBverify\\fR exits 3 when the task is disproved and 4 when it stays"
  echo "undecided; \\fBfit --certify\\fR exits 0 with a certified bracket, 3 when every design it tried"
  echo "was disproved, 4 otherwise."
  echo ".SH SEE ALSO"
  echo ".BR paraview (1)"
  echo "for the .vti volumes and meshes,"
  echo ".BR mpirun (1)"
  echo "for distributed sweeps; the MuJoCo documentation for the models \\fBexport-model\\fR writes."
} | gzip -9n >"$tmp"
mv -f "$tmp" "$out"
trap - EXIT

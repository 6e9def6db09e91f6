#!/usr/bin/env bash
# Usage: packaging/check-deb.sh BUILD_DIR
#
# Builds the Debian package of an already built tree (cpack -G DEB, run in
# BUILD_DIR) and checks it WITHOUT installing it: control fields and Depends
# (dpkg-deb -I), the file list, then runs the binary extracted with
# dpkg-deb -x -- --help, a forward-kinematics eval that must find the
# packaged preset through <exe>/../share/linkscape/mechanisms, fields of the
# 12R, the Delta and PATHOS-II on the baseline SIMD target against each
# device's reference kernel, and, when DISPLAY is set,
# --screenshot. Prints one PASS/FAIL/SKIP line per check and
# exits non-zero if any check failed. On success the package is also copied
# to BUILD_DIR/linkscape_<version>_<arch>.deb.
#
# All work happens in a private temporary directory (cpack -B), so parallel
# ctest runs and other users of BUILD_DIR are not disturbed.
set -uo pipefail

if [ $# -ne 1 ] || [ ! -f "$1/CPackConfig.cmake" ]; then
  echo "usage: $0 BUILD_DIR   (a configured and built Linkscape tree)" >&2
  exit 2
fi
build=$(cd "$1" && pwd)

work=$(mktemp -d "${TMPDIR:-/tmp}/linkscape-check-deb.XXXXXX")
trap 'rm -rf "$work"' EXIT

failures=0
pass() { echo "PASS: $*"; }
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
skip() { echo "SKIP: $*"; }
finish() {
  if [ "$failures" -eq 0 ]; then
    echo "check-deb: all checks passed"
    exit 0
  fi
  echo "check-deb: $failures check(s) FAILED"
  exit 1
}
# Runs a command with a time limit, output to $work/<name>.log; shows the log on failure.
run() {
  local name=$1; shift
  timeout 60 "$@" >"$work/$name.log" 2>&1
  local rc=$?
  [ $rc -eq 0 ] || { echo "---- $name (exit $rc): $*"; tail -n 30 "$work/$name.log"; echo "----"; }
  return $rc
}

version=$(sed -n 's/^set(CPACK_PACKAGE_VERSION "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
arch=$(dpkg --print-architecture)
deb_name="linkscape_${version}_${arch}.deb"

# --- 1. build the package -------------------------------------------------
start=$(date +%s)
if (cd "$build" && run cpack cpack -G DEB -B "$work/out" --config "$build/CPackConfig.cmake"); then
  pass "cpack -G DEB ($(($(date +%s) - start)) s)"
else
  fail "cpack -G DEB"
  finish
fi
deb="$work/out/$deb_name"
if [ -s "$deb" ]; then
  pass "package file is $deb_name ($(du -k "$deb" | cut -f1) KiB)"
else
  fail "expected $deb_name, cpack wrote: $(cd "$work/out" && ls -- *.deb 2>/dev/null | tr '\n' ' ')"
  finish
fi

# --- 2. control fields ----------------------------------------------------
dpkg-deb -I "$deb" >"$work/info.txt" 2>&1 || fail "dpkg-deb -I"
field() { dpkg-deb -f "$deb" "$1" 2>/dev/null; }
echo "---- dpkg-deb -I $deb_name"
cat "$work/info.txt"
echo "----"
check_field() {  # name expected
  local got; got=$(field "$1")
  if [ "$got" = "$2" ]; then pass "$1: $got"; else fail "$1 is '$got', expected '$2'"; fi
}
check_field Package linkscape
check_field Version "$version"
check_field Architecture "$arch"
maintainer=$(field Maintainer)
if [[ $maintainer =~ ^[^\<]+\ \<[^@\>]+@[^\>]+\>$ ]]; then pass "Maintainer: $maintainer"
else fail "Maintainer is '$maintainer', expected 'Name <address>'"; fi
check_field Section science
if [ -z "$(field Homepage)" ]; then pass "no Homepage field"; else fail "unexpected Homepage: $(field Homepage)"; fi
if [ -n "$(field Description)" ]; then pass "Description: $(field Description | head -n1)"; else fail "no Description"; fi
depends=$(field Depends)
echo "Depends: $depends"
# Package names in Depends, one a line, without versions or alternatives.
dep_names=$(sed 's/([^)]*)//g; s/[|,]/\n/g' <<<"$depends" | tr -d ' ' | sed '/^$/d')
missing=()
for lib in libc6 libstdc++6 libgomp1 libhwy1 libqt6core6 libqt6gui6 libqt6widgets6 libqt6opengl6 libqt6charts6 libvtk9.1; do
  grep -qxF "$lib" <<<"$dep_names" || missing+=("$lib")
done
if [ ${#missing[@]} -eq 0 ]; then pass "Depends names libc6, libstdc++6, libgomp1, Highway, Qt6 (with Charts) and VTK 9.1"
else fail "Depends lacks: ${missing[*]}"; fi
# The binary links libmpi (linkscape sweep over MPI ranks, and Debian's VTK):
# its package must be named.
if [ -n "$(objdump -p "$build/gui/linkscape" 2>/dev/null | grep 'NEEDED *libmpi')" ]; then
  if grep -qxF libopenmpi3 <<<"$dep_names"; then pass "Depends names libopenmpi3 (the binary links libmpi)"
  else fail "the binary links libmpi but Depends lacks libopenmpi3"; fi
fi
# Every dependency must be installable here (the build machine has them all).
unresolved=()
for pkg in $dep_names; do
  dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || unresolved+=("$pkg")
done
if [ ${#unresolved[@]} -eq 0 ]; then pass "every package in Depends is installed on this machine"
else fail "Depends names packages not installed here: ${unresolved[*]}"; fi

# --- 3. contents ----------------------------------------------------------
dpkg-deb -c "$deb" | awk '{print $NF}' >"$work/contents.txt"
for f in ./usr/bin/linkscape \
         ./usr/share/linkscape/mechanisms/parallel-12r.json \
         ./usr/share/man/man1/linkscape.1.gz \
         ./usr/share/bash-completion/completions/linkscape \
         ./usr/share/doc/linkscape/copyright \
         ./usr/share/doc/linkscape/changelog.gz \
         ./usr/share/doc/linkscape/README.md \
         ./usr/share/doc/linkscape/docs/architecture.md \
         ./usr/share/doc/linkscape/docs/images/window-12r.png \
         ./usr/share/applications/linkscape.desktop \
         ./usr/share/icons/hicolor/scalable/apps/linkscape.svg \
         ./usr/share/icons/hicolor/256x256/apps/linkscape.png; do
  if grep -qxF "$f" "$work/contents.txt"; then pass "contains ${f#.}"; else fail "missing ${f#.}"; fi
done

root="$work/root"
mkdir -p "$root"
if dpkg-deb -x "$deb" "$root"; then pass "dpkg-deb -x"; else fail "dpkg-deb -x"; finish; fi

desktop="$root/usr/share/applications/linkscape.desktop"
if [ -f "$desktop" ]; then
  for kv in "Name=Linkscape" "Exec=linkscape %f" "Icon=linkscape" "Terminal=false" \
            "Categories=Science;Engineering;"; do
    grep -qxF "$kv" "$desktop" || fail "desktop entry lacks '$kv'"
  done
  if command -v desktop-file-validate >/dev/null; then
    # Nothing at all may be reported, not even a hint.
    if desktop-file-validate "$desktop" >"$work/dfv.log" 2>&1 && [ ! -s "$work/dfv.log" ]; then
      pass "desktop-file-validate linkscape.desktop"
    else
      fail "desktop-file-validate: $(cat "$work/dfv.log")"
    fi
  else
    fail "desktop-file-validate is not installed (packaging/install-deps.sh installs it)"
  fi
fi
man="$root/usr/share/man/man1/linkscape.1.gz"
# The page read whole first: `zcat | head -n1` would end zcat with SIGPIPE,
# which pipefail counts as a failure once the page outgrows a pipe's buffer.
page=$([ -f "$man" ] && zcat "$man" || true)
if grep -q '^\.TH LINKSCAPE 1' <<<"$(sed -n 1p <<<"$page")" && [ "$(grep -c '^\.SS ' <<<"$page")" -ge 5 ]; then
  pass "manual page has a title and a section per command ($(grep -c '^\.SS ' <<<"$page"))"
else
  fail "manual page is missing its title or its command sections"
fi
for section in EXAMPLES WINDOW ENVIRONMENT FILES "EXIT STATUS" "SEE ALSO"; do
  if grep -qx "\.SH \"\?$section\"\?" <<<"$page"; then pass "manual page has $section"
  else fail "manual page lacks its $section section"; fi
done
# The window's shortcuts, from the program itself (linkscape --shortcuts).
if grep -q '^Help > Documentation  *F1$' <<<"$page"; then pass "manual page lists the window's shortcuts"
else fail "manual page lists no window shortcuts (F1)"; fi
# The help text is preformatted on the page and indented by 7: within 80
# columns when each of its lines is at most 73 (the page's own lines fill).
wide=$(zcat "$man" 2>/dev/null | awk '/^\.nf/ {pre = 1; next} /^\.fi/ {pre = 0} pre && length($0) > 73 {n++} END {print n + 0}')
if [ -f "$man" ] && [ "$wide" -eq 0 ]; then
  pass "manual page's help text fits 80 columns"
else
  fail "manual page has $wide preformatted lines wider than 73 characters"
fi
completion="$root/usr/share/bash-completion/completions/linkscape"
if [ -f "$completion" ] && bash -n "$completion" && grep -q 'complete -F _linkscape linkscape' "$completion"; then
  pass "bash completion parses and registers _linkscape"
else
  fail "bash completion does not parse or register"
fi
# It completes what the program says: a preset name after -m, with help of any width.
completed=$(bash -c 'source /usr/share/bash-completion/bash_completion 2>/dev/null; source "$1"
  PATH="$2:$PATH"; COMP_WORDS=(linkscape eval -m del); COMP_CWORD=3; COMP_LINE="linkscape eval -m del"
  COMP_POINT=${#COMP_LINE}; _linkscape linkscape del -m; echo "${COMPREPLY[*]}"' _ "$completion" "$build/gui" 2>/dev/null)
if [[ " $completed " == *" delta "* ]]; then
  pass "bash completion offers the presets after -m ($completed)"
else
  fail "bash completion after '-m del' gave '$completed', expected delta among them"
fi
# ... and the values of an enumerated option, from linkscape --complete-values.
completed=$(bash -c 'source /usr/share/bash-completion/bash_completion 2>/dev/null; source "$1"
  PATH="$2:$PATH"; COMP_WORDS=(linkscape slice --colour-map ci); COMP_CWORD=3; COMP_LINE="linkscape slice --colour-map ci"
  COMP_POINT=${#COMP_LINE}; _linkscape linkscape ci --colour-map; echo "${COMPREPLY[*]}"' _ "$completion" "$build/gui" 2>/dev/null)
if [ "$completed" = "cividis" ]; then
  pass "bash completion offers an option's values (--colour-map ci: $completed)"
else
  fail "bash completion after '--colour-map ci' gave '$completed', expected cividis"
fi
if command -v lintian >/dev/null; then
  # lintian warns when run as root; that is about the checker, not the package.
  if lintian --fail-on error,warning "$deb" >"$work/lintian.log" 2>&1; then
    pass "lintian: no errors or warnings"
  else
    fail "lintian: $(grep -E '^[EW]:' "$work/lintian.log" | head -n 10)"
  fi
else
  fail "lintian is not installed (packaging/install-deps.sh installs it)"
fi
png="$root/usr/share/icons/hicolor/256x256/apps/linkscape.png"
if [ -f "$png" ]; then
  read -r w h < <(od -An -tu1 -j16 -N8 "$png" |
                  awk '{print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8}')
  if [ "$(od -An -tx1 -N8 "$png" | tr -d ' \n')" = 89504e470d0a1a0a ] && [ "$w" = 256 ] && [ "$h" = 256 ]; then
    pass "256x256 icon is a 256x256 PNG"
  else
    fail "256x256 icon is not a 256x256 PNG (${w}x${h})"
  fi
fi
svg="$root/usr/share/icons/hicolor/scalable/apps/linkscape.svg"
if [ -f "$svg" ] && grep -q 'viewBox="0 0 256 256"' "$svg"; then pass "scalable icon is an SVG"
elif [ -f "$svg" ]; then fail "scalable icon has no 256x256 viewBox"; fi

# --- 4. run the extracted binary -----------------------------------------
exe="$root/usr/bin/linkscape"
# Only the packaged preset directory may be used: no LINKSCAPE_ASSETS.
# (The binary also falls back to the source tree it was built from; step
# 4b proves the packaged copy is the one read.)
run_exe() { local name=$1; shift; (cd "$work" && run "$name" env -u LINKSCAPE_ASSETS "$exe" "$@"); }

if run_exe help --help && grep -q "eval" "$work/help.log"; then
  pass "linkscape --help (exit 0)"
else
  fail "linkscape --help"
fi

printf 'alpha,beta,gamma\n0,0,1.5707963267948966\n' >"$work/angles.csv"
# Prints the x,y,z of the first data row of an eval --fk output.
endpoint() { awk -F, 'NR==1{for(i=1;i<=NF;i++)c[$i]=i; next} NR==2{print $c["x"], $c["y"], $c["z"]}' "$1"; }
near() {  # x y z ex ey ez: all within 1e-6
  awk -v x="$1" -v y="$2" -v z="$3" -v a="$4" -v b="$5" -v c="$6" 'function d(u,v){return u>v?u-v:v-u}
      BEGIN{exit !(x!="" && d(x,a)<1e-6 && d(y,b)<1e-6 && d(z,c)<1e-6)}'
}
if run_exe eval eval --mechanism parallel-12r --fk "$work/angles.csv" -o "$work/fk.csv"; then
  read -r x y z < <(endpoint "$work/fk.csv")
  if near "$x" "$y" "$z" 0 15 15; then
    pass "eval --fk with the packaged preset: endpoint ($x, $y, $z) = (0, 15, 15)"
  else
    fail "eval --fk endpoint is ($x, $y, $z), expected (0, 15, 15)"; cat "$work/fk.csv"
  fi
else
  fail "linkscape eval --mechanism parallel-12r --fk"
fi

# 4b. Change the extracted preset only: the result must follow it, so the
# binary really reads <exe>/../share/linkscape/mechanisms.
preset="$root/usr/share/linkscape/mechanisms/parallel-12r.json"
if [ -f "$preset" ] && sed -i 's/"L1": *15\.0/"L1": 21.0/; s/"L2": *15\.0/"L2": 23.0/' "$preset" &&
   grep -q '"L1": 21.0' "$preset" && grep -q '"L2": 23.0' "$preset"; then
  if run_exe eval-moved eval --mechanism parallel-12r --fk "$work/angles.csv" -o "$work/fk2.csv"; then
    read -r x y z < <(endpoint "$work/fk2.csv")
    if near "$x" "$y" "$z" 0 21 23; then
      pass "preset is found relative to the binary (edited packaged copy gives ($x, $y, $z))"
    else
      fail "edited packaged preset was not used: endpoint ($x, $y, $z), expected (0, 21, 23)"
    fi
  else
    fail "linkscape eval with the edited packaged preset"
  fi
else
  fail "cannot edit the packaged preset's L1/L2 (format changed?)"
fi

# 4c. As on a CPU with only the baseline instruction set (SSE2): the
# vectorised fields forced to Highway's portable target.
field_csv() {  # name file mechanism [VAR=value]: a field at 21^3 as CSV
  local name=$1 file=$2 mechanism=$3; shift 3
  (cd "$work" && run "$name" env -u LINKSCAPE_ASSETS "$@" "$exe" field --mechanism "$mechanism" \
     --resolution 21 --output "$file")
}
# The 12R's, the Delta's and PATHOS-II's kernels are vectorised: the
# statuses, reachable flags, iterations and methods must be the reference's,
# the measures (c(J); PATHOS-II's cond(Jp) and cond(Jo)) within a float
# rounding, the reach margin and residual within 1e-5 (length unit; the file
# prints floats).
for device in parallel-12r delta pathos2; do
  measures=1
  [ "$device" = pathos2 ] && measures=2
  if field_csv "$device-baseline" "$work/$device-baseline.csv" "$device" LINKSCAPE_SIMD_TARGET=baseline &&
     field_csv "$device-scalar" "$work/$device-scalar.csv" "$device" LINKSCAPE_FIELD_KERNEL=scalar; then
    # Columns: x,y,z, the measures, reach_margin,residual,reachable,status,iterations,method_used
    if paste -d, "$work/$device-baseline.csv" "$work/$device-scalar.csv" | awk -F, -v m="$measures" '
         function off(a, b) { return a == b ? 0 : (a - b < 0 ? b - a : a - b) }
         NR == 1 { w = NF / 2; next }
         { n++; for (i = 6 + m; i <= w; i++) if ($i != $(i + w)) bad++
           for (i = 4; i < 4 + m; i++) { a = ($i < 0 ? -$i : $i); if (off($i, $(i + w)) > 2.4e-7 * a) bad++ }
           if (off($(4 + m), $(4 + m + w)) > 1e-5 || off($(5 + m), $(5 + m + w)) > 1e-5) bad++ }
       END { exit !(n == 9261 && bad == 0) }'; then
      pass "$device field on the baseline SIMD target agrees with the reference kernel (9261 samples)"
    else
      fail "$device field on the baseline SIMD target differs from the reference kernel"
    fi
  else
    fail "linkscape field -m $device with LINKSCAPE_SIMD_TARGET=baseline / LINKSCAPE_FIELD_KERNEL=scalar"
  fi
done

if [ -n "${DISPLAY:-}" ]; then
  if run_exe screenshot --screenshot "$work/out.png" && [ -s "$work/out.png" ]; then
    pass "linkscape --screenshot ($(du -k "$work/out.png" | cut -f1) KiB PNG)"
  else
    fail "linkscape --screenshot (exit 0 and a non-empty file expected)"
  fi
else
  skip "linkscape --screenshot: DISPLAY is not set"
fi

# --- 5. hand the package over ---------------------------------------------
if [ "$failures" -eq 0 ]; then
  cp "$deb" "$build/.$deb_name.$$" && mv -f "$build/.$deb_name.$$" "$build/$deb_name" &&
    echo "check-deb: package at $build/$deb_name"
fi
finish

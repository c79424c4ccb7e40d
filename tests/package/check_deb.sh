#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The Debian package made by .ci/package, checked as a user gets it:
#   check_deb.sh BUILD_DIR SOURCE_DIR VERSION PYTHON (the interpreter the module was built for)
# its file list (dpkg-deb -c), its control fields, `apt-get install --simulate` of it, the binary, the
# Python module, the man pages and the bash completion run from the extracted package (dpkg-deb -x; nothing
# of the build or source tree on the paths), and lintian without errors. Exit 77 (skipped) when the package
# was not built, unless DTF_REQUIRE_TOOLS=1.
set -uo pipefail
build=$1 source=$2 version=$3 py=$4
pyver=$("$py" -c 'import sys; print("%d.%d" % sys.version_info[:2])')
arch=$(dpkg --print-architecture)
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)
deb=$(realpath "$build/package/dtfabric_${version}_${arch}.deb" 2>/dev/null || echo "$build/package/dtfabric_${version}_${arch}.deb")
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
ok() { echo "ok: $*"; }

if [ ! -f "$deb" ]; then
  echo "$deb not found: run .ci/package first" >&2
  case "${DTF_REQUIRE_TOOLS:-}" in ''|0) exit 77 ;; *) exit 1 ;; esac
fi
if [ "$build/app/dtfabric" -nt "$deb" ]; then
  fail "$deb is older than $build/app/dtfabric: run .ci/package again"
fi

# The install line of the README and the guide and the Containerfile's default name this package.
for doc in README.md sample_data/guide/README.md app/workflow/Containerfile app/workflow/README.md; do
  grep -qF "dtfabric_${version}_${arch}.deb" "$source/$doc" && ok "$doc names dtfabric_${version}_${arch}.deb" ||
    fail "$doc does not name dtfabric_${version}_${arch}.deb"
done

# ---- file list ----
list=$(dpkg-deb -c "$deb") || { echo "dpkg-deb -c failed" >&2; exit 1; }
files=$(awk '{print $6}' <<<"$list" | sed 's|^\./|/|')
need() { grep -qxE "$1" <<<"$files" && ok "has $1" || fail "no file matching $1 in the package"; }
need '/usr/bin/dtfabric'
need "/usr/lib/$multiarch/libdtfabric\\.so\\.${version%.*}(\\.[0-9]+)?"
need "/usr/lib/$multiarch/libdtfabric\\.so"
need "/usr/lib/$multiarch/cmake/dtfabric/dtfabricConfig\\.cmake"
need "/usr/lib/$multiarch/cmake/dtfabric/dtfabricTargets\\.cmake"
need '/usr/include/dtfabric/dtfabric\.h'
need '/usr/include/dtfabric/render/embedding\.h|/usr/include/dtfabric/render/.*\.h'
need '/usr/lib/python3/dist-packages/dtfabric/__init__\.py'
need '/usr/lib/python3/dist-packages/dtfabric/_core\..*\.so'
need '/usr/share/dtfabric/dwi\.nii\.gz'
need '/usr/share/dtfabric/dwi\.bval'
need '/usr/share/dtfabric/dwi\.bvec'
need '/usr/share/man/man1/dtfabric\.1\.gz'
need '/usr/share/man/man1/dtfabric-render\.1\.gz'
need '/usr/share/bash-completion/completions/dtfabric'
need '/usr/share/doc/dtfabric/copyright'
need '/usr/share/doc/dtfabric/changelog\.gz'
if grep -qE '__pycache__|\.pyc$|/build/|/test_scratch/' <<<"$files"; then
  fail "build leftovers in the package: $(grep -E '__pycache__|\.pyc$|/build/|/test_scratch/' <<<"$files" | head -3)"
fi

# ---- control fields ----
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for d in libc6 libstdc++6 python3-numpy "python3 (>= $pyver~)" libegl1 libepoxy0 libvtk libnifti libgl1-mesa-dri; do
  grep -qF "$d" <<<"$depends" && ok "Depends names $d" || fail "Depends lacks $d"
done
[ "$(dpkg-deb -f "$deb" Version)" = "$version" ] && ok "Version $version" || fail "Version is not $version"

# ---- apt resolves the dependencies ----
sim=$(apt-get install --simulate -q "$deb" 2>&1)
if [ $? -eq 0 ] && grep -q '^Inst dtfabric\|dtfabric is already the newest' <<<"$sim"; then
  ok "apt-get install --simulate: $(grep -c '^Inst' <<<"$sim") package(s) to install"
else
  fail "apt-get install --simulate did not resolve: $(tail -5 <<<"$sim")"
fi

# ---- run from the extracted package ----
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
dpkg-deb -x "$deb" "$root/x"
mkdir "$root/run"
cd "$root/run" || exit 1
export LD_LIBRARY_PATH="$root/x/usr/lib/$multiarch" PYTHONPATH="$root/x/usr/lib/python3/dist-packages"
exe=$root/x/usr/bin/dtfabric
v=$("$exe" --version) && [ "$v" = "dtfabric $version" ] && ok "--version: $v" || fail "--version printed '$v'"
if "$exe" render "$root/x/usr/share/dtfabric/dwi.nii.gz" -o brain.png --surface slice=axial:22 --size 256x256 \
    >render.log 2>&1 && "$py" -c "import sys; d = open('brain.png', 'rb').read(); sys.exit(d[:8] != b'\x89PNG\r\n\x1a\n')"; then
  ok "the packaged dtfabric renders the packaged brain"
else
  fail "render of the packaged brain: $(tail -3 render.log)"
fi
if "$py" -c "
import dtfabric, numpy
assert dtfabric.__file__.startswith('$root/x/'), dtfabric.__file__
f = dtfabric.TensorField(numpy.tile(numpy.array([2e-3, 0, 0, 5e-4, 0, 5e-4], numpy.float32), (8, 8, 8, 1)), numpy.eye(4), layout='world')
img = dtfabric.render(f, size=(64, 64))
assert img.shape == (64, 64, 4) and img[..., :3].max() > 0
t = dtfabric.load('$root/x/usr/share/dtfabric/dwi.nii.gz')
assert t.tensor.shape[:3] == (72, 72, 39), t.tensor.shape
" >python.log 2>&1; then
  ok "the packaged Python module imports, renders and loads the packaged brain"
else
  fail "Python module from the package: $(tail -3 python.log)"
fi

# The man pages and the completion are what the packaged binary generates from its tables.
for page in $("$exe" help --man-pages); do
  gz=$root/x/usr/share/man/man1/$page.1.gz
  if [ ! -f "$gz" ]; then fail "no man page $page"; continue; fi
  cmp -s <(gzip -dc "$gz") <("$exe" help --man "$page") || fail "$page.1.gz differs from \`dtfabric help --man $page\`"
  warnings=$(LC_ALL=C.UTF-8 MANROFFSEQ='' MANWIDTH=80 man --warnings -E UTF-8 -l -Tutf8 -Z "$gz" 2>&1 >/dev/null)
  [ -z "$warnings" ] || fail "man warnings in $page: $warnings"
done
ok "$("$exe" help --man-pages | wc -l) man pages equal the binary's and format without warnings"
comp=$root/x/usr/share/bash-completion/completions/dtfabric
cmp -s "$comp" <("$exe" help --bash-completion) || fail "the completion differs from \`dtfabric help --bash-completion\`"
got=$(bash -c "source '$comp'; COMP_WORDS=(dtfabric ren); COMP_CWORD=1; _dtfabric; echo \"\${COMPREPLY[*]}\"")
[ "$got" = render ] && ok "completion: dtfabric ren<TAB> -> $got" || fail "completion of 'dtfabric ren' gave '$got'"

# ---- lintian ----
cd / || exit 1
lint=$(lintian --fail-on error --tag-display-limit 0 "$deb" 2>&1)
lint_rc=$?
echo "$lint" | sed 's/^/lintian: /'
if [ "$lint_rc" -ne 0 ] || grep -q '^E:' <<<"$lint"; then
  fail "lintian reports errors (exit $lint_rc)"
else
  ok "lintian: no error ($(grep -c '^W:' <<<"$lint") warning(s))"
fi

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "package OK: $deb"

#!/usr/bin/env bash
# Installed as users install things (CTest packaging.*): `cmake --install`, the Debian package of
# `cpack -G DEB`, and `pip install .`; each installed program and module must run from where it went.
# Usage: check-packaging.sh install|deb|pip SOURCE_DIR BUILD_DIR
set -euo pipefail
what=$1 src=$2 build=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
version=$(sed -n 's/^project(symphong VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")

check_program() {  # the installed program and its man page
    "$1/bin/symphong" --version | grep -q "^symphong $version\$" || fail "$1/bin/symphong --version"
    "$1/bin/symphong" render -W 8 -H 8 -s 2 -o "$tmp/x.png" > /dev/null || fail "the installed program cannot render"
    local page="$1/share/man/man1/symphong.1.gz"  # gzipped, as Debian's policy asks
    gzip -t "$page" 2>/dev/null || fail "no gzipped man page in $1/share/man/man1"
    gzip -dc "$page" | grep -q '^\.TH SYMPHONG 1' || fail "the man page in $1/share/man/man1 has no .TH header"
    gzip -dc "$page" | grep -q 'symphong render' || fail "the man page lacks the render command"
}
check_module() {  # the installed module, imported from its directory only
    (cd "$tmp" && PYTHONPATH="$1" python3 -c "
import symphong, sys
assert symphong.__file__.startswith('$1'), symphong.__file__
assert symphong.__version__ == '$version', symphong.__version__
img, stats = symphong.render('cornell', spp=2, width=8, height=6, progress=False)
assert img.shape == (6, 8, 3)
") || fail "the module installed in $1"
}

case "$what" in
install)
    cmake --install "$build" --prefix "$tmp/prefix" --component program > /dev/null
    cmake --install "$build" --prefix "$tmp/prefix" --component debian_python > /dev/null
    check_program "$tmp/prefix"
    check_module "$tmp/prefix/lib/python3/dist-packages"
    ;;
deb)
    (cd "$build" && cpack -G DEB -B "$tmp/deb" > "$tmp/cpack.log" 2>&1) || { cat "$tmp/cpack.log"; fail "cpack -G DEB"; }
    deb=$(ls "$tmp"/deb/*.deb)
    dpkg-deb -c "$deb" | awk '{print $6}' > "$tmp/contents"
    for f in ./usr/bin/symphong ./usr/share/man/man1/symphong.1.gz; do grep -qx "$f" "$tmp/contents" || fail "$f not in the package"; done
    grep -q '^\./usr/lib/python3/dist-packages/symphong\..*\.so$' "$tmp/contents" || fail "the module is not in the package"
    dpkg-deb -f "$deb" Depends | grep -q 'libembree3' || fail "the package does not depend on Embree"
    dpkg-deb -x "$deb" "$tmp/root"
    check_program "$tmp/root/usr"
    check_module "$tmp/root/usr/lib/python3/dist-packages"
    ;;
pip)
    SYMPHONG_CMAKE_BUILD_DIR="$build" python3 -m pip install --no-build-isolation --no-index --no-deps --quiet \
        --target "$tmp/site" "$src" 2>&1 | grep -v "Running pip as the 'root' user" || true
    ls "$tmp"/site/symphong-*.dist-info > /dev/null || fail "pip installed no symphong distribution"
    check_module "$tmp/site"
    ;;
*) fail "unknown check $what" ;;
esac
echo "ok: $what"

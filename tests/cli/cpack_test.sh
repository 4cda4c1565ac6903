#!/usr/bin/env bash
# Runs CPack's DEB generator on the build directory's CPackConfig.cmake into a temporary directory
# and checks the package's name, version, dependencies and contents. Fails without dpkg-deb. Usage: cpack_test.sh CPACK BUILD_DIR VERSION
set -uo pipefail
cpack=${1:?cpack}
build=${2:?build directory}
version=${3:?version}

command -v dpkg-deb >/dev/null 2>&1 || {
  echo "FAIL: dpkg-deb not found (Debian package dpkg)"
  exit 1
}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}

"$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$tmp" >"$tmp/cpack.log" 2>&1 ||
  fail "cpack -G DEB: $(cat "$tmp/cpack.log")"
debs=("$tmp"/*.deb)
[ ${#debs[@]} -eq 1 ] && [ -f "${debs[0]}" ] || fail "expected one .deb in $tmp: $(ls "$tmp")"
deb=${debs[0]}

fields=$(dpkg-deb -f "$deb") || fail "dpkg-deb -f $deb"
grep -qx "Package: dxlemu" <<<"$fields" || fail "control fields:"$'\n'"$fields"
grep -qx "Version: $version" <<<"$fields" || fail "not version $version:"$'\n'"$fields"
grep -qE "^Depends: .*libc6" <<<"$fields" || fail "no Depends on libc6:"$'\n'"$fields"
grep -qx "Recommends: libjs-three, libjs-chart.js" <<<"$fields" ||
  fail "no Recommends of the web page's libraries:"$'\n'"$fields"
grep -qE "^Maintainer: .+ <.+>$" <<<"$fields" || fail "no Maintainer NAME <EMAIL>:"$'\n'"$fields"

contents=$(dpkg-deb -c "$deb") || fail "dpkg-deb -c $deb"
for path in ./usr/bin/dxlemu ./usr/share/dxlemu/models/catalog.json \
  ./usr/share/dxlemu/models/xm430-w350.json ./usr/share/dxlemu/models/schema/model.schema.json \
  ./usr/share/dxlemu/robots/so101-follower.json ./usr/share/doc/dxlemu/README.md \
  ./usr/share/dxlemu/web/index.html ./usr/share/dxlemu/web/api.js; do
  grep -qE " $path\$" <<<"$contents" || fail "$path not in the package:"$'\n'"$contents"
done
# The Python package where Debian's python3 finds it, with its dist-info, and the path from it
# to the binary installed with it.
site=./usr/lib/python3/dist-packages
for path in "$site/dxlemu/__init__.py" "$site/dxlemu/pytest_plugin.py" "$site/dxlemu/_installed.py" \
  "$site/dxlemu-$version.dist-info/METADATA" "$site/dxlemu-$version.dist-info/entry_points.txt" \
  "$site/dxlemu-$version.dist-info/RECORD"; do
  grep -qE " $path\$" <<<"$contents" || fail "$path not in the package:"$'\n'"$contents"
done
installed=$(dpkg-deb --fsys-tarfile "$deb" | tar -xO "$site/dxlemu/_installed.py") ||
  fail "cannot read $site/dxlemu/_installed.py"
grep -qx "BINARY = '../../../../bin/dxlemu'" <<<"$installed" ||
  fail "$site/dxlemu/_installed.py does not lead to /usr/bin/dxlemu:"$'\n'"$installed"
# The preload library of `dxlemu exec`, in CMAKE_INSTALL_LIBDIR's dxlemu/ (lib or lib/<multiarch>).
preload='./usr/lib(/[^/]+)?/dxlemu/libdxlemu-preload\.so'
grep -qE " $preload\$" <<<"$contents" || fail "libdxlemu-preload.so not in the package:"$'\n'"$contents"
# The executable is the only file in usr/bin; nothing else (tests, fuzzers, other libraries) ships.
others=$(grep -E '^-' <<<"$contents" |
  grep -vE " ./usr/(bin/dxlemu|share/dxlemu/(models|robots|web)/|share/doc/dxlemu/)| $preload\$" |
  grep -vE " $site/dxlemu(/[a-z_]+\.py|-$version\.dist-info/[A-Za-z_.]+)\$")
[ -z "$others" ] || fail "unexpected files in the package:"$'\n'"$others"

echo "ok: $(basename "$deb"): Package dxlemu $version with bin/dxlemu, the preload library, the model library, the robot profiles, the web page and the Python package"

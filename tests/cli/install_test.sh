#!/usr/bin/env bash
# `cmake --install` into a temporary prefix, then checks that the installed dxlemu finds the
# installed model library relative to itself, in preference to the source tree's models/, and
# that its `dxlemu exec` finds the installed preload library the same way.
# Usage: install_test.sh CMAKE BUILD_DIR SOURCE_MODELS_DIR VERSION
set -uo pipefail
cmake=${1:?cmake}
build=${2:?build directory}
source_models=${3:?source models directory}
version=${4:?version}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() {
  echo "FAIL: $*"
  exit 1
}

# models_listing PROGRAM: sets out to `PROGRAM models` run with DXLEMU_MODELS_DIR unset.
models_listing() {
  out=$(env -u DXLEMU_MODELS_DIR "$1" models 2>&1) || fail "$1 models exited $?:"$'\n'"$out"
}
# lists LISTING NAME: whether the `dxlemu models` LISTING has a row for model NAME.
lists() { grep -qE "^$2 " <<<"$1"; }

prefix=$tmp/prefix
"$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1 ||
  fail "cmake --install: $(cat "$tmp/install.log")"

# What is installed: the binary, the preload library, the model library, the docs, the Python
# package; no test, fuzz or bench target.
models=$prefix/share/dxlemu/models
[ -x "$prefix/bin/dxlemu" ] || fail "no bin/dxlemu"
[ -f "$models/catalog.json" ] || fail "no share/dxlemu/models/catalog.json"
[ -f "$models/schema/model.schema.json" ] || fail "no share/dxlemu/models/schema/model.schema.json"
[ -f "$prefix/share/doc/dxlemu/README.md" ] || fail "no share/doc/dxlemu/README.md"
installed_count=$(find "$models" -maxdepth 1 -name '*.json' | wc -l)
source_count=$(find "$source_models" -maxdepth 1 -name '*.json' | wc -l)
[ "$installed_count" -eq "$source_count" ] ||
  fail "$installed_count model files installed, $source_count in $source_models"
[ "$(ls "$prefix")" = "$(printf 'bin\nlib\nshare')" ] || fail "prefix holds: $(ls "$prefix")"
[ "$(ls "$prefix/bin")" = "dxlemu" ] || fail "bin/ holds: $(ls "$prefix/bin")"

# The Python package in lib/python3/dist-packages with its dist-info (tests/packaging checks
# that Python and pytest use them).
site=$prefix/lib/python3/dist-packages
[ "$(ls "$site")" = "$(printf 'dxlemu\ndxlemu-%s.dist-info' "$version")" ] ||
  fail "lib/python3/dist-packages holds: $(ls "$site")"
for module in __init__.py daemon.py pytest_plugin.py _installed.py; do
  [ -f "$site/dxlemu/$module" ] || fail "no lib/python3/dist-packages/dxlemu/$module"
done

# The library directory is CMAKE_INSTALL_LIBDIR's (lib, lib64 or lib/<multiarch>), then dxlemu/.
mapfile -t preloads < <(cd "$prefix" && find . -name 'libdxlemu-preload.so*' | sort)
[[ "${preloads[*]}" =~ ^\./lib[^/\ ]*(/[^/\ ]+)?/dxlemu/libdxlemu-preload\.so$ ]] ||
  fail "preload libraries installed: ${preloads[*]:-none}"
preload=${preloads[0]#./}

# exec_preload PROGRAM: sets out to the LD_PRELOAD `PROGRAM exec` gives a command (/dev/null is a
# character device, so --port accepts it).
exec_preload() {
  out=$(env -u DXLEMU_PRELOAD -u LD_PRELOAD "$1" exec --port /dev/null -- sh -c 'echo "$LD_PRELOAD"' 2>&1) ||
    fail "$1 exec exited $?:"$'\n'"$out"
}
exec_preload "$prefix/bin/dxlemu"
[ "$out" = "$prefix/$preload" ] || fail "installed dxlemu exec preloads \"$out\", not $prefix/$preload"

# The whole library is listed without DXLEMU_MODELS_DIR.
models_listing "$prefix/bin/dxlemu"
lists "$out" xm430-w350 && lists "$out" ax-12a || fail "installed dxlemu models lists:"$'\n'"$out"

# The robot profiles are installed beside the models and the installed copy is the one used: a
# profile removed from it is no longer listed, though the source tree's robots/ still has it.
robots=$prefix/share/dxlemu/robots
[ -f "$robots/so101-follower.json" ] || fail "no share/dxlemu/robots/so101-follower.json"
[ -f "$robots/poppy-ergo-jr.json" ] || fail "no share/dxlemu/robots/poppy-ergo-jr.json"
rm "$robots/poppy-ergo-jr.json"
out=$(env -u DXLEMU_ROBOTS_DIR "$prefix/bin/dxlemu" robots 2>&1) || fail "installed dxlemu robots: $out"
lists "$out" so101-follower && ! lists "$out" poppy-ergo-jr ||
  fail "installed dxlemu robots did not use share/dxlemu/robots:"$'\n'"$out"

# The installed copy wins over the source tree: a catalog of one model lists one model.
cat >"$models/catalog.json" <<'EOF'
{
  "models": [
    {
      "name": "xm430-w350",
      "title": "XM430-W350",
      "model_number": 1020,
      "family": "x",
      "protocols": [2, 1],
      "file": "xm430-w350.json"
    }
  ]
}
EOF
models_listing "$prefix/bin/dxlemu"
lists "$out" xm430-w350 && ! lists "$out" ax-12a ||
  fail "with the installed catalog cut to xm430-w350, dxlemu models lists:"$'\n'"$out"

# Still so when the prefix moves, and when the binary is started through a symlink elsewhere.
mv "$prefix" "$tmp/moved"
prefix=$tmp/moved
mkdir "$tmp/links"
ln -s "$prefix/bin/dxlemu" "$tmp/links/dxlemu"
for program in "$prefix/bin/dxlemu" "$tmp/links/dxlemu"; do
  models_listing "$program"
  lists "$out" xm430-w350 && ! lists "$out" ax-12a ||
    fail "$program (moved prefix) did not use the installed catalog:"$'\n'"$out"
  exec_preload "$program"
  [ "$out" = "$prefix/$preload" ] || fail "$program (moved prefix) exec preloads \"$out\""
done

# Without the library, exec says where it looked and runs nothing.
mv "$prefix/$preload" "$tmp/preload.so"
out=$(env -u DXLEMU_PRELOAD "$prefix/bin/dxlemu" exec --port /dev/null -- true 2>&1)
status=$?
[ "$status" -eq 125 ] && grep -q "libdxlemu-preload.so was not found (looked at .*$prefix/$preload)" <<<"$out" ||
  fail "exec without its library exited $status:"$'\n'"$out"
mv "$tmp/preload.so" "$prefix/$preload"

# $DXLEMU_MODELS_DIR still overrides the installed copy.
out=$(DXLEMU_MODELS_DIR=$source_models "$prefix/bin/dxlemu" models 2>&1) || fail "$out"
lists "$out" ax-12a || fail "DXLEMU_MODELS_DIR=$source_models was ignored:"$'\n'"$out"

# Without a catalog.json beside it, the binary falls back to the source tree's models/.
rm "$prefix/share/dxlemu/models/catalog.json"
models_listing "$prefix/bin/dxlemu"
lists "$out" ax-12a || fail "no fallback to $source_models:"$'\n'"$out"

echo "ok: installed dxlemu uses share/dxlemu/models and robots beside its bin/, after \$DXLEMU_MODELS_DIR, before the source tree; its exec preloads $preload"

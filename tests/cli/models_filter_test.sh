#!/usr/bin/env bash
# `dxlemu models` filters against the whole listing: each filter, alone and combined, lists
# exactly the rows of the whole listing that meet it, under the same header, in the same order
# and format. Data-driven over whatever the library holds.
# Usage: models_filter_test.sh DXLEMU
set -uo pipefail
dxlemu=${1:?dxlemu}

fail() {
  echo "FAIL: $*"
  exit 1
}

all=$("$dxlemu" models) || fail "dxlemu models exited $?"
header=$(head -n 1 <<<"$all")

# expect_rows AWK_CONDITION ARGS...: `dxlemu models ARGS` is the header and the rows of the whole
# listing that meet AWK_CONDITION (columns: name, number, protocols, family), at least one.
expect_rows() {
  local condition=$1
  shift
  local expected got
  expected=$(tail -n +2 <<<"$all" | awk "$condition")
  [ -n "$expected" ] || fail "no row of the whole listing meets $condition: a useless case"
  got=$("$dxlemu" models "$@") || fail "dxlemu models $* exited $?"
  [ "$(head -n 1 <<<"$got")" = "$header" ] || fail "dxlemu models $*: header changed: $got"
  if [ "$(tail -n +2 <<<"$got")" != "$expected" ]; then
    echo "FAIL: dxlemu models $* (expected the rows where $condition)"
    diff <(echo "$expected") <(tail -n +2 <<<"$got")
    exit 1
  fi
  echo "ok: dxlemu models $*: $(wc -l <<<"$expected") of $(($(wc -l <<<"$all") - 1)) rows"
}

expect_rows '$4 == "x"' --family x
expect_rows '$4 == "ax"' --family ax
expect_rows '$3 ~ /(^|,)1\.0/' --protocol 1
expect_rows '$3 ~ /(^|,)2\.0/' --protocol 2
expect_rows '$3 ~ /(^|,)modbus($|,)/' --protocol modbus
# Lowercase names hold the titles' letters: a fragment in capitals finds them.
expect_rows '$1 ~ /430/' --name 430
expect_rows '$1 ~ /xm/' --name XM
expect_rows '$4 == "x" && $3 ~ /1\.0/ && $1 ~ /540/' --family x --protocol 1 --name 540

# A filter that matches nothing: nothing on stdout (not even the header), the reason on stderr,
# exit status 0.
errors=$(mktemp)
trap 'rm -f "$errors"' EXIT
out=$("$dxlemu" models --name no-such-model 2>"$errors") || fail "no match exited $?"
[ -z "$out" ] || fail "no match printed on stdout: $out"
grep -q '^dxlemu: no model matches --name no-such-model' "$errors" ||
  fail "no match: stderr was: $(cat "$errors")"
echo "ok: dxlemu models --name no-such-model: stdout empty, stderr $(cat "$errors")"

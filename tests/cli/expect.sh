#!/usr/bin/env bash
# Runs a command and checks its exit code and output: expect.sh CODE REGEX -- COMMAND [ARGS...]
# Passes when the command exits with CODE and its combined stdout/stderr matches the extended
# regular expression REGEX. Prints what it got otherwise.
set -uo pipefail
code=$1
regex=$2
shift 3
output=$("$@" 2>&1)
status=$?
if [ "$status" -ne "$code" ] || ! grep -qE -- "$regex" <<<"$output"; then
  echo "expected exit $code and output matching: $regex"
  echo "got exit $status and output:"
  echo "$output"
  exit 1
fi
echo "ok: exit $status, output matches $regex"

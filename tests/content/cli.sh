#!/bin/sh
# Command-line behaviour of vergence-content.
# usage: sh tests/content/cli.sh TOOL TMPDIR
set -u
tool=$1 tmp=$2
fails=0
check() { # check NAME WANT_RC [args...]
  name=$1 want=$2
  shift 2
  "$tool" "$@" >"$tmp.out" 2>"$tmp.err"
  rc=$?
  if [ "$rc" -ne "$want" ]; then
    echo "FAIL $name: exit $rc, want $want"; cat "$tmp.err"; fails=$((fails + 1)); return
  fi
  if [ "$want" -ne 0 ] && [ "$(wc -l <"$tmp.err")" -ne 1 ]; then
    echo "FAIL $name: want exactly one error line, got:"; cat "$tmp.err"; fails=$((fails + 1)); return
  fi
  echo "ok   $name (exit $rc)"
}
rm -rf "$tmp"
check help 0 --help
grep -q "usage: vergence-content --out DIR" "$tmp.out" || { echo "FAIL help: no usage line"; fails=$((fails + 1)); }
check list 0 --list
check no-out 2
check out-without-value 2 --out
check unknown-option 2 --out "$tmp" --frobnicate
check unknown-scene 2 --out "$tmp" --scene nope
check one-scene 0 --out "$tmp" --scene cubes
if [ -s "$tmp/cubes.gltf" ] && [ -s "$tmp/cubes.bin" ] && [ ! -e "$tmp/balloon.gltf" ]; then
  echo "ok   one-scene wrote only cubes"
else
  echo "FAIL one-scene: expected only cubes.gltf and cubes.bin in $tmp"; fails=$((fails + 1))
fi
touch "$tmp.file"
check out-is-a-file 3 --out "$tmp.file/sub"
rm -f "$tmp.file" "$tmp.out" "$tmp.err"
[ "$fails" -eq 0 ] || { echo "$fails checks failed"; exit 1; }
echo "all checks passed"

#!/bin/sh
# vergence — runs one test (the arguments) with a temporary directory of its
# own as TMPDIR, which Python's tempfile and the C tests' scratch files use.
# A passing test leaves nothing behind; a failing one keeps its directory
# for a look and says where. (Tests made their directories under /tmp and
# never removed them: a suite run left 1-2 GB there.)
# VG_TEST_PRELOAD becomes the test's LD_PRELOAD (the leak checks preload the
# sanitizer runtime: this shell and its mktemp must not run under it).
d=$(mktemp -d "${TMPDIR:-/tmp}/vergence-test.XXXXXX") || exit 1
if [ -n "${VG_TEST_PRELOAD:-}" ]; then
    TMPDIR=$d LD_PRELOAD=$VG_TEST_PRELOAD "$@"
else
    TMPDIR=$d "$@"
fi
rc=$?
if [ "$rc" -eq 0 ]; then
    rm -rf "$d"
else
    echo "tmpdir.sh: the test's files are kept in $d" >&2
fi
exit "$rc"

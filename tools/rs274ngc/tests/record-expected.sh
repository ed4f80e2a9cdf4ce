#!/bin/bash
# Record what LinuxCNC's own rs274 prints for each program in programs/:
# programs/expected/NAME.out is its standard output and
# programs/expected/NAME.err is "exit N" followed by its standard error.
# tests/programs.rs runs our rs274 the same way and compares byte for byte.
#
# usage: LINUXCNC_RS274=/path/to/usr/bin/rs274 tests/record-expected.sh [NAME...]
#
# The libraries are looked for next to the binary (../lib and
# ../lib/x86_64-linux-gnu) unless LINUXCNC_LD_LIBRARY_PATH names them.
# Each program runs in a fresh copy of programs/ (a -v parameter file is
# rewritten by the run) with "-t tool.tbl" unless its NAME.args has -t,
# then the words of NAME.args, then "-g NAME.ngc".
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
programs="$here/programs"
rs274=${LINUXCNC_RS274:?set LINUXCNC_RS274 to LinuxCNC\'s rs274 binary}
bindir=$(cd "$(dirname "$rs274")" && pwd)
libs=${LINUXCNC_LD_LIBRARY_PATH:-$bindir/../lib:$bindir/../lib/x86_64-linux-gnu}

if [ $# -eq 0 ]; then
    set -- $(cd "$programs" && ls *.ngc | sed 's/\.ngc$//')
fi
mkdir -p "$programs/expected"
for name in "$@"; do
    work=$(mktemp -d)
    cp -r "$programs/." "$work/"
    args=()
    if [ -f "$programs/$name.args" ]; then
        read -r -a args < "$programs/$name.args"
    fi
    case " ${args[*]-} " in
        *" -t "*) ;;
        *) args=(-t tool.tbl "${args[@]}") ;;
    esac
    set +e
    (cd "$work" && LD_LIBRARY_PATH="$libs" timeout 20 "$rs274" "${args[@]}" -g "$name.ngc" \
        > "$work/.out" 2> "$work/.err" < /dev/null)
    status=$?
    set -e
    cp "$work/.out" "$programs/expected/$name.out"
    { echo "exit $status"; cat "$work/.err"; } > "$programs/expected/$name.err"
    rm -rf "$work"
    echo "$name: exit $status"
done

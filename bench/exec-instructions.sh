#!/usr/bin/env bash
# Counts the instructions the executor spends per cycle and per function,
# a figure the machine's load does not move (unlike its time), with
# valgrind's callgrind on hal-core's exec_cost bench.
#
#   bench/exec-instructions.sh [-n N] [-s SECS] [SHAPE...]
#
#   -n N     functions in the chain (default 100)
#   -s SECS  how long each configuration runs under valgrind (default 2)
#   SHAPE    sum2, and2 or trivial (default all three)
#
# For each shape and for timing on and off it runs the bench's `one`
# configuration twice, with N chained functions and with none, counting
# only the instructions of the executor thread's body (the toggle on
# hal_core::exec::thread::run and what it calls) and dividing by the
# cycles that ran. The thread alone is its fixed cost per cycle (with the
# bench's one recording function); (with - without) / N is the cost per
# function, the function's own body included. Callgrind serialises the
# threads and runs them slowly, so the figures are instructions, never
# time.
set -euo pipefail

n=100
secs=2
while getopts "n:s:h" opt; do
    case $opt in
        n) n=$OPTARG ;;
        s) secs=$OPTARG ;;
        *) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
shapes=${*:-sum2 and2 trivial}

command -v valgrind >/dev/null || { echo "valgrind is not installed" >&2; exit 1; }
top=$(cd "$(dirname "$0")/.." && pwd)
cd "$top"
CARGO_INCREMENTAL=0 nice cargo bench -p hal-core --bench exec_cost --no-run 2>/dev/null
bin=$(ls -t target/release/deps/exec_cost-* | grep -v '\.d$' | head -1)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

# per_cycle SHAPE TIMING COUNT: instructions per cycle of the executor.
per_cycle() {
    local log="$out/$1-$2-$3"
    nice valgrind --tool=callgrind --callgrind-out-file=/dev/null \
        --toggle-collect='hal_core::exec::thread::run' \
        "$bin" one "$1" "$2" "$3" "$secs" > "$log.out" 2> "$log.err"
    local ir cycles
    ir=$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$log.err")
    cycles=$(sed -n 's/^cycles \([0-9]*\).*/\1/p' "$log.out")
    [ -n "$ir" ] && [ -n "$cycles" ] && [ "$cycles" -gt 0 ] || {
        echo "no figure for $1 $2 $3:" >&2
        cat "$log.err" "$log.out" >&2
        exit 1
    }
    echo $((ir / cycles))
}

echo "instructions of the executor thread (callgrind), $n chained functions"
printf '%-8s %-8s %14s %14s\n' shape timing "thread alone" "per function"
for shape in $shapes; do
    for timing in timed untimed; do
        alone=$(per_cycle "$shape" "$timing" 0)
        full=$(per_cycle "$shape" "$timing" "$n")
        printf '%-8s %-8s %14d %14.1f\n' "$shape" "$timing" "$alone" \
            "$(echo "($full - $alone) / $n" | bc -l)"
    done
done

#!/bin/sh
# Runs the same HAL files on this project's halrun and, when a LinuxCNC
# installation is given, on LinuxCNC's, alternating runs, and prints the
# medians and the ratios (ours / LinuxCNC).
#
#   bench/side-by-side.sh [-r RUNS] [-n SAMPLES] [-b OUR_BIN_DIR] [-l LINUXCNC_DIR]
#
# OUR_BIN_DIR holds halrun and halsampler (default: target/release, built
# with `cargo build --release -p hal-tools` if missing). LINUXCNC_DIR is a
# run-in-place tree (scripts/rip-environment is sourced) or an installation
# prefix (its bin/halrun is used). HAL_NO_REALTIME=1 in the environment
# runs ours without realtime scheduling; LinuxCNC's uspace build follows
# its own permissions. SIDE_BY_SIDE_KEEP=1 keeps the HAL files and outputs.
#
# Every case samples the thread's own `t.time` pin (the time of the
# previous cycle's functions and the executor's work between them) with a
# sampler in the same thread, for SAMPLES cycles of a 1 ms thread:
#   sampler-only     the sampler alone: a thread's fixed cost plus the sampler
#   sum2 x100        100 chained sum2 (each output through a signal into the
#                    next one's input) and the sampler
#   and2 x100        the same with and2
#   sum2 x100 untimed  ours only: timing1=0, no per-function .time/.tmax
# and derives the per-function cost as (case - sampler-only) / 100.
set -eu

runs=5
samples=2000
ours=""
lcnc=""
while getopts r:n:b:l:h opt; do
    case $opt in
    r) runs=$OPTARG ;;
    n) samples=$OPTARG ;;
    b) ours=$OPTARG ;;
    l) lcnc=$OPTARG ;;
    *) sed -n '2,27p' "$0"; exit 2 ;;
    esac
done

top=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "$ours" ]; then
    ours=$top/target/release
    if [ ! -x "$ours/halrun" ] || [ ! -x "$ours/halsampler" ]; then
        (cd "$top" && cargo build --release -p hal-tools --bin halrun --bin halsampler)
    fi
fi
ours=$(cd "$ours" && pwd)
for b in halrun halsampler; do
    [ -x "$ours/$b" ] || { echo "side-by-side: $ours/$b is missing" >&2; exit 1; }
done
if [ -n "$lcnc" ]; then
    lcnc=$(cd "$lcnc" && pwd)
    if [ ! -f "$lcnc/scripts/rip-environment" ] && [ ! -x "$lcnc/bin/halrun" ]; then
        echo "side-by-side: $lcnc is neither a run-in-place tree nor has bin/halrun" >&2
        exit 1
    fi
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/side-by-side.XXXXXX")
[ -n "${SIDE_BY_SIDE_KEEP:-}" ] || trap 'rm -rf "$work"' EXIT

# make_case NAME COMPONENT COUNT THREAD_EXTRA: writes $work/NAME.hal.
make_case() {
    name=$1 comp=$2 count=$3 extra=$4
    f=$work/$name.hal
    {
        echo "loadrt threads name1=t period1=1000000 $extra"
        echo "loadrt sampler cfg=s depth=$((samples + 100))"
        if [ "$count" -gt 0 ]; then
            echo "loadrt $comp count=$count"
            i=0
            while [ $i -lt "$count" ]; do
                echo "addf $comp.$i t"
                if [ $i -gt 0 ]; then
                    echo "net c$i $comp.$((i - 1)).out => $comp.$i.in0"
                fi
                i=$((i + 1))
            done
        fi
        echo "net thread-time t.time => sampler.0.pin.0"
        echo "addf sampler.0 t"
        echo "start"
        echo "loadusr -w halsampler -n $samples"
    } > "$f"
}

make_case sampler-only sum2 0 ""
make_case sum2 sum2 100 ""
make_case and2 and2 100 ""
make_case sum2-untimed sum2 100 "timing1=0"

# run_case IMPL NAME: prints the median of the sampled thread times (ns),
# skipping the first 100 cycles (pages faulting in, caches warming).
run_case() {
    impl=$1 name=$2
    out=$work/$impl-$name.out
    if [ "$impl" = ours ]; then
        (cd "$work" && PATH="$ours:$PATH" "$ours/halrun" -f "$name.hal") > "$out" 2>"$out.err" || true
    else
        (
            cd "$work"
            if [ -f "$lcnc/scripts/rip-environment" ]; then
                . "$lcnc/scripts/rip-environment" >/dev/null
                halrun -f "$name.hal"
            else
                PATH="$lcnc/bin:$PATH" "$lcnc/bin/halrun" -f "$name.hal"
            fi
        ) > "$out" 2>"$out.err" || true
    fi
    tail -n +101 "$out" | awk 'NF >= 1 && $1 ~ /^-?[0-9]+$/ { print $1 }' | sort -n |
        awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else print v[int((NR + 1) / 2)] }'
}

median() {
    tr ' ' '\n' | grep -v '^-*$' | sort -n |
        awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else print v[int((NR + 1) / 2)] }'
}

cases="sampler-only sum2 and2 sum2-untimed"
impls=ours
[ -n "$lcnc" ] && impls="ours lcnc"
r=1
while [ $r -le "$runs" ]; do
    for c in $cases; do
        for i in $impls; do
            [ "$i" = lcnc ] && [ "$c" = sum2-untimed ] && continue
            v=$(run_case "$i" "$c")
            echo "$v" >> "$work/$i-$c.runs"
        done
    done
    r=$((r + 1))
done

get() { if [ -f "$work/$1-$2.runs" ]; then median < "$work/$1-$2.runs"; else echo -; fi; }
per_funct() {
    [ "$1" = - ] || [ "$2" = - ] && { echo -; return; }
    awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", (a - b) / 100 }'
}
ratio() {
    [ "$1" = - ] || [ "$2" = - ] && { echo -; return; }
    awk -v a="$1" -v b="$2" 'BEGIN { if (b <= 0) print "-"; else printf "%.2f", a / b }'
}

echo "thread time of a 1 ms thread, median of $runs alternating runs of $samples cycles (ns)"
printf '%-22s %10s %10s %8s\n' case ours linuxcnc ratio
for c in $cases; do
    o=$(get ours "$c") l=$(get lcnc "$c")
    printf '%-22s %10s %10s %8s\n' "$c" "$o" "$l" "$(ratio "$o" "$l")"
done
echo "per function, (case - sampler-only) / 100 (ns)"
so=$(get ours sampler-only) sl=$(get lcnc sampler-only)
for c in sum2 and2 sum2-untimed; do
    o=$(per_funct "$(get ours "$c")" "$so") l=$(per_funct "$(get lcnc "$c")" "$sl")
    printf '%-22s %10s %10s %8s\n' "$c" "$o" "$l" "$(ratio "$o" "$l")"
done

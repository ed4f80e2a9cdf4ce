#!/bin/sh
# Runs the same HAL files on this project's halrun and, when a LinuxCNC
# installation is given, on LinuxCNC's, alternating runs, and prints the
# medians and the ratios (ours / LinuxCNC).
#
#   bench/side-by-side.sh [-r RUNS] [-n SAMPLES] [-L LATENCY_SAMPLES]
#                         [-b OUR_BIN_DIR] [-l LINUXCNC_DIR]
#
# OUR_BIN_DIR holds halrun, halcmd, hal-host, halsampler and halstreamer (default:
# target/release, built with `cargo build --release -p hal-tools` if one is
# missing). LINUXCNC_DIR is a run-in-place tree (scripts/rip-environment is
# sourced) or an installation prefix (its bin/halrun is used).
# HAL_NO_REALTIME=1 in the environment runs ours without realtime
# scheduling; LinuxCNC's uspace build follows its own permissions (it uses
# SCHED_FIFO only where it finds a realtime kernel, or with
# LINUXCNC_FORCE_REALTIME=1). SIDE_BY_SIDE_KEEP=1 keeps the HAL files and
# outputs and prints where they are.
#
# Every timing case samples the thread's own `t.time` pin (the time of the
# previous cycle's functions and the executor's work between them) with a
# sampler in the same thread, for SAMPLES cycles of a 1 ms thread:
#   sampler-only     the sampler alone: a thread's fixed cost plus the sampler
#   sum2 x100        100 chained sum2 (each output through a signal into the
#                    next one's input) and the sampler
#   and2 x100        the same with and2
#   sum2 x100 untimed  ours only: timing1=0, no per-function .time/.tmax
#   streamer         a one-column streamer (its FIFO filled by halstreamer
#                    before start) and the sampler
# and derives the per-function cost as (case - sampler-only) / 100, and the
# streamer's as (streamer - sampler-only).
#
# During the sampler-only case the script also reads the CPU time the
# kernel charges to the thread (/proc/PID/task/TID/schedstat) over one
# second: the whole cost of a cycle, wake-up and context switches included.
#
# The latency case runs timedelta alone on a 1 ms thread and samples its
# `out` pin (ns between this run and the previous one) for LATENCY_SAMPLES
# cycles; the figures are |out - 1 ms| over every run, p50/p99/p99.9/max.
set -eu

runs=5
samples=2000
lat_samples=5000
ours=""
lcnc=""
while getopts r:n:L:b:l:h opt; do
    case $opt in
    r) runs=$OPTARG ;;
    n) samples=$OPTARG ;;
    L) lat_samples=$OPTARG ;;
    b) ours=$OPTARG ;;
    l) lcnc=$OPTARG ;;
    *) sed -n '2,34p' "$0"; exit 2 ;;
    esac
done

top=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "$ours" ]; then
    ours=$top/target/release
    for b in halrun halcmd hal-host halsampler halstreamer; do
        if [ ! -x "$ours/$b" ]; then
            (cd "$top" && cargo build --release -p hal-tools --bin halrun \
                --bin halcmd --bin hal-host --bin halsampler --bin halstreamer)
            break
        fi
    done
fi
ours=$(cd "$ours" && pwd)
for b in halrun halcmd hal-host halsampler halstreamer; do
    [ -x "$ours/$b" ] || { echo "side-by-side: $ours/$b is missing" >&2; exit 1; }
done
if [ -n "$lcnc" ]; then
    lcnc=$(cd "$lcnc" && pwd)
    if [ ! -f "$lcnc/scripts/rip-environment" ] && [ ! -x "$lcnc/bin/halrun" ]; then
        echo "side-by-side: $lcnc is neither a run-in-place tree nor has bin/halrun" >&2
        exit 1
    fi
fi

# A private directory (mktemp makes it 0700 under a random name).
work=$(mktemp -d "${TMPDIR:-/tmp}/side-by-side.XXXXXX")
if [ -n "${SIDE_BY_SIDE_KEEP:-}" ]; then
    echo "side-by-side: files kept in $work"
else
    trap 'rm -rf "$work"' EXIT
fi

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

# The CPU probe reads the sampler-only thread for 1.5 s: at least 2000 cycles.
full=$samples
[ "$samples" -ge 2000 ] || samples=2000
make_case sampler-only sum2 0 ""
samples=$full
make_case sum2 sum2 100 ""
make_case and2 and2 100 ""
make_case sum2-untimed sum2 100 "timing1=0"
awk -v n="$((samples + 200))" 'BEGIN { for (i = 0; i < n; i++) print (i % 100) / 10 }' \
    > "$work/stream.txt"
cat > "$work/streamer.hal" <<EOF
loadrt threads name1=t period1=1000000
loadrt streamer cfg=f depth=$((samples + 300))
loadrt sampler cfg=s depth=$((samples + 100))
addf streamer.0 t
net thread-time t.time => sampler.0.pin.0
addf sampler.0 t
loadusr -w halstreamer stream.txt
start
loadusr -w halsampler -n $samples
EOF
cat > "$work/latency.hal" <<EOF
loadrt threads name1=t period1=1000000
loadrt timedelta count=1
loadrt sampler cfg=s depth=$((lat_samples + 100))
addf timedelta.0 t
net interval timedelta.0.out => sampler.0.pin.0
addf sampler.0 t
start
loadusr -w halsampler -n $lat_samples
EOF

# run_hal IMPL NAME: runs NAME.hal on IMPL, output in $work/IMPL-NAME.out.
run_hal() {
    if [ "$1" = ours ]; then
        (cd "$work" && PATH="$ours:$PATH" "$ours/halrun" -f "$2.hal")
    else
        (
            cd "$work"
            if [ -f "$lcnc/scripts/rip-environment" ]; then
                . "$lcnc/scripts/rip-environment" >/dev/null
                halrun -f "$2.hal"
            else
                PATH="$lcnc/bin:$PATH" "$lcnc/bin/halrun" -f "$2.hal"
            fi
        )
    fi > "$work/$1-$2.out" 2> "$work/$1-$2.out.err" || true
}

# find_task COMM: the /proc directory of the first task named COMM.
find_task() {
    for t in /proc/[0-9]*/task/[0-9]*; do
        c=$(cat "$t/comm" 2>/dev/null) || continue
        if [ "$c" = "$1" ]; then
            echo "$t"
            return
        fi
    done
}

# thread_cpu IMPL: CPU ns per 1 ms cycle charged to IMPL's thread `t`, read
# over one second once the thread has been running for half a second.
thread_cpu() {
    if [ "$1" = ours ]; then comm=hal-t; else comm="rtapi_app:T#0"; fi
    tries=0 task=""
    while [ -z "$task" ] && [ $tries -lt 50 ]; do
        sleep 0.1
        task=$(find_task "$comm")
        tries=$((tries + 1))
    done
    [ -n "$task" ] || { echo -; return; }
    sleep 0.5
    c0=$(cut -d' ' -f1 "$task/schedstat" 2>/dev/null) || { echo -; return; }
    w0=$(date +%s%N)
    sleep 1
    c1=$(cut -d' ' -f1 "$task/schedstat" 2>/dev/null) || { echo -; return; }
    w1=$(date +%s%N)
    awk -v c="$((c1 - c0))" -v w="$((w1 - w0))" 'BEGIN { printf "%.0f\n", c * 1e6 / w }'
}

# samples_of FILE [SKIP]: the integers in the first column of FILE after
# SKIP lines (the first cycles fault pages in and warm caches).
samples_of() {
    tail -n +"$((${2:-100} + 1))" "$1" | awk 'NF >= 1 && $1 ~ /^-?[0-9]+$/ { print $1 }'
}

median() {
    grep -v '^-*$' | sort -n |
        awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else print v[int((NR + 1) / 2)] }'
}

cases="sampler-only sum2 and2 sum2-untimed streamer"
impls=ours
[ -n "$lcnc" ] && impls="ours lcnc"
r=1
while [ $r -le "$runs" ]; do
    for c in $cases latency; do
        for i in $impls; do
            [ "$i" = lcnc ] && [ "$c" = sum2-untimed ] && continue
            if [ "$c" = sampler-only ]; then
                run_hal "$i" "$c" &
                thread_cpu "$i" >> "$work/$i-cpu.runs"
                wait $!
            else
                run_hal "$i" "$c"
            fi
            if [ "$c" = latency ]; then
                samples_of "$work/$i-$c.out" |
                    awk '{ d = $1 - 1000000; print (d < 0 ? -d : d) }' >> "$work/$i-latency.all"
            else
                samples_of "$work/$i-$c.out" | median >> "$work/$i-$c.runs"
            fi
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
# percentile IMPL P: the P-th percentile (0..1, 1 = max) of IMPL's latencies.
percentile() {
    f=$work/$1-latency.all
    [ -s "$f" ] || { echo -; return; }
    sort -n "$f" | awk -v p="$2" '{ v[NR] = $1 }
        END { i = int(NR * p + 0.999999); if (i < 1) i = 1; if (i > NR) i = NR; print v[i] }'
}
row() { printf '%-22s %10s %10s %8s\n' "$1" "$2" "$3" "$(ratio "$2" "$3")"; }

echo "thread time of a 1 ms thread, median of $runs alternating runs of $samples cycles (ns)"
printf '%-22s %10s %10s %8s\n' case ours linuxcnc ratio
for c in $cases; do
    row "$c" "$(get ours "$c")" "$(get lcnc "$c")"
done
echo "per function, (case - sampler-only) / 100 (ns)"
so=$(get ours sampler-only) sl=$(get lcnc sampler-only)
for c in sum2 and2 sum2-untimed; do
    row "$c" "$(per_funct "$(get ours "$c")" "$so")" "$(per_funct "$(get lcnc "$c")" "$sl")"
done
echo "streamer function, streamer - sampler-only (ns)"
difference() {
    [ "$1" = - ] || [ "$2" = - ] && { echo -; return; }
    echo $(($1 - $2))
}
row streamer "$(difference "$(get ours streamer)" "$so")" \
    "$(difference "$(get lcnc streamer)" "$sl")"
echo "CPU charged to the sampler-only thread per cycle, median of $runs runs (ns)"
row sampler-thread "$(get ours cpu)" "$(get lcnc cpu)"
echo "1 ms interval error |timedelta.out - 1 ms| over $runs x $lat_samples cycles (ns)"
for p in p50:0.5 p99:0.99 p99.9:0.999 max:1; do
    row "${p%%:*}" "$(percentile ours "${p#*:}")" "$(percentile lcnc "${p#*:}")"
done

#!/usr/bin/env bash
# Runs the same HAL files on this project's halrun and on LinuxCNC 2.9's
# (the peer unpacked by scripts/linuxcnc-peer), alternating runs and which
# side goes first, and prints the medians and the ratios (ours / LinuxCNC)
# with the machine's load during each series.
#
#   bench/side-by-side.sh [-r RUNS] [-n SAMPLES] [-L LATENCY_SAMPLES]
#                         [-b OUR_BIN_DIR] [-s SERIES] [-c CPU] [-R] [-P] [-C]
#
#   -r RUNS      alternating runs of every case (default 5)
#   -n SAMPLES   cycles sampled per timing case (default 2000)
#   -L N         cycles sampled per latency case (default 5000)
#   -b DIR       our halrun, halcmd, hal-host, halsampler, halstreamer
#                (default target/release, built if one is missing)
#   -s SERIES    "defaults", "matched" or "both" (default both):
#                defaults  each side as it runs out of the box;
#                matched   both alike: the threads on CPU (-c, default the
#                          last one), timer slack 1 ns, a zero CPU wake-up
#                          latency request, and ours without its short
#                          scheduler slice (LinuxCNC has none)
#   -R           realtime: SCHED_FIFO on both sides (LinuxCNC with
#                LINUXCNC_FORCE_REALTIME=1 and the shim below); without it
#                both run as ordinary threads (ours with HAL_NO_REALTIME=1)
#   -P           ours only, no LinuxCNC
#   -C           also check the units with a known disturbance (below)
#
# Units. LinuxCNC 2.9's uspace build times threads and functions with a
# bare rdtsc and stores the difference unscaled: its `.time` pins are TSC
# ticks. Ours are ns. The script measures the TSC rate against
# CLOCK_MONOTONIC_RAW at the start (bench/tsc-hz.c) and converts
# LinuxCNC's thread times to ns before comparing; the output says so.
# The interval error (timedelta) is ns on both sides.
#
# With -C, bench/burst.c runs at SCHED_FIFO 99 on the threads' CPU and
# busy-waits 1500 us every 3001 us while a long function list runs
# (sum2 x400); a burst that lands inside the list lengthens that cycle's
# thread time by 1500 us. The median excess over the median thread time in
# the cycles hit, divided by the burst, must come out near 1 on both sides
# after the conversion.
#
# Every timing case samples the thread's own `t.time` pin (the time of
# the previous cycle's functions and the executor's work between them)
# with a sampler in the same thread, for SAMPLES cycles of a 1 ms thread:
#   sampler-only     the sampler alone: a thread's fixed cost plus the sampler
#   sum2 x100        100 chained sum2 (each output through a signal into the
#                    next one's input) and the sampler
#   and2 x100        the same with and2
#   sum2 x100 untimed  ours only: timing1=0, no per-function .time/.tmax
#   streamer         a one-column streamer (its FIFO filled by halstreamer
#                    before start) and the sampler
#   parport          one of our drivers in both hosts: hal_parport on its
#                    simulated port (cfg="0 sim"), parport.0.read and
#                    parport.0.write, and the sampler. LinuxCNC loads the
#                    same driver built as its module (linuxcnc-modules/
#                    hal_parport, laid over its own by the peer script's -m)
# and derives the per-function cost as (case - sampler-only) / 100, the
# streamer's as (streamer - sampler-only), and the driver's read+write as
# (parport - sampler-only).
#
# During the sampler-only case the script also reads the CPU time the
# kernel charges to the thread (/proc/PID/task/TID/schedstat) over one
# second. The thread is found inside the run's own processes (those that
# carry the run's token in their environment), never by name across the
# machine.
#
# The latency case runs timedelta alone on a 1 ms thread and samples its
# `out` pin (ns between this run and the previous one) for LATENCY_SAMPLES
# cycles; the figures are |out - 1 ms| over every run, p50/p99/p99.9/max.
#
# LinuxCNC runs through scripts/linuxcnc-peer (LINUXCNC_PEER_PREFIX picks
# the prefix), with bench/peer-shim.c preloaded: it makes iopl() and the
# RLIMIT_RTPRIO raise report success (a VM's kernel and a sandbox refuse
# them, and rtapi_app wants both before SCHED_FIFO) and, for the matched
# series, sets rtapi_app's timer slack and latency request. The shim and
# the two helpers are built with cc into the run's private directory.
# SIDE_BY_SIDE_KEEP=1 keeps the HAL files and outputs.
set -euo pipefail

runs=5
samples=2000
lat_samples=5000
ours=""
series=both
cpu=""
realtime=""
with_peer=1
check=""
while getopts r:n:L:b:s:c:RPCh opt; do
    case $opt in
    r) runs=$OPTARG ;;
    n) samples=$OPTARG ;;
    L) lat_samples=$OPTARG ;;
    b) ours=$OPTARG ;;
    s) series=$OPTARG ;;
    c) cpu=$OPTARG ;;
    R) realtime=1 ;;
    P) with_peer="" ;;
    C) check=1 ;;
    *) sed -n '2,76p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
    esac
done
case $series in defaults | matched | both) ;; *) echo "side-by-side: -s takes defaults, matched or both" >&2; exit 2 ;; esac

top=$(cd "$(dirname "$0")/.." && pwd)
bins="halrun halcmd hal-host halsampler halstreamer"
if [ -z "$ours" ]; then
    ours=$top/target/release
    for b in $bins; do
        if [ ! -x "$ours/$b" ]; then
            (cd "$top" && cargo build --release -p hal-tools --bin halrun \
                --bin halcmd --bin hal-host --bin halsampler --bin halstreamer)
            break
        fi
    done
fi
# Our hal_parport as a LinuxCNC module, for the driver case on LinuxCNC.
module_so=$top/target/release/liblcnc_hal_parport.so
if [ -n "$with_peer" ] && [ ! -f "$module_so" ]; then
    (cd "$top" && cargo build --release -p lcnc-hal-parport)
fi
ours=$(cd "$ours" && pwd)
for b in $bins; do
    [ -x "$ours/$b" ] || { echo "side-by-side: $ours/$b is missing" >&2; exit 1; }
done
peer=$top/scripts/linuxcnc-peer
if [ -n "$with_peer" ] && ! "$peer" prefix >/dev/null; then
    echo "side-by-side: LinuxCNC is not unpacked (scripts/linuxcnc-peer install), or give -P" >&2
    exit 1
fi
[ -n "$cpu" ] || cpu=$(($(nproc) - 1))

# A private directory (mktemp makes it 0700 under a random name).
work=$(mktemp -d "${TMPDIR:-/tmp}/side-by-side.XXXXXX")
if [ -n "${SIDE_BY_SIDE_KEEP:-}" ]; then
    echo "side-by-side: files kept in $work"
else
    trap 'rm -rf "$work"' EXIT
fi
chmod 0755 "$work" # LinuxCNC runs as the user nobody; it reads the HAL files.

cc -O2 -o "$work/tsc-hz" "$top/bench/tsc-hz.c"
[ -z "$check" ] || cc -O2 -o "$work/burst" "$top/bench/burst.c"
if [ -n "$with_peer" ]; then
    cc -O2 -shared -fPIC -o "$work/peer-shim.so" "$top/bench/peer-shim.c" -ldl
    mkdir -p "$work/modules"
    cp "$module_so" "$work/modules/hal_parport.so"
fi
tsc_hz=$("$work/tsc-hz")

# make_case NAME COMPONENT COUNT THREAD_EXTRA [SAMPLES]: writes $work/NAME.hal.
make_case() {
    local name=$1 comp=$2 count=$3 extra=$4 n=${5:-$samples}
    {
        echo "loadrt threads name1=t period1=1000000 $extra"
        echo "loadrt sampler cfg=s depth=$((n + 100))"
        if [ "$count" -gt 0 ]; then
            echo "loadrt $comp count=$count"
            local i=0
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
        echo "loadusr -w halsampler -n $n"
    } > "$work/$name.hal"
}

# The CPU probe reads the sampler-only thread for 1.5 s: at least 2000 cycles.
make_case sampler-only sum2 0 "" "$((samples < 2000 ? 2000 : samples))"
make_case sum2 sum2 100 ""
make_case and2 and2 100 ""
make_case sum2-untimed sum2 100 "timing1=0"
make_case burst-check sum2 400 "" 4000
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
cat > "$work/parport.hal" <<EOF
loadrt threads name1=t period1=1000000
loadrt hal_parport cfg="0 sim"
loadrt sampler cfg=s depth=$((samples + 100))
addf parport.0.read t
addf parport.0.write t
net thread-time t.time => sampler.0.pin.0
addf sampler.0 t
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

# run_hal IMPL SERIES NAME TOKEN: runs NAME.hal on IMPL, output in
# $work/SERIES/IMPL-NAME.out; every process of the run carries TOKEN.
run_hal() {
    local impl=$1 ser=$2 name=$3 token=$4
    local out=$work/$ser/$impl-$name.out
    local env=(SBS_RUN_TOKEN="$token")
    if [ "$impl" = ours ]; then
        env+=(HAL_INSTANCE="sbs-$token" PATH="$ours:$PATH")
        [ -n "$realtime" ] || env+=(HAL_NO_REALTIME=1)
        [ "$ser" = defaults ] || env+=(RTAPI_CPU_NUMBER="$cpu" HAL_NO_SHORT_SLICE=1)
        (cd "$work" && env "${env[@]}" "$ours/halrun" -f "$name.hal")
    else
        env+=(LD_PRELOAD="$work/peer-shim.so")
        [ -z "$realtime" ] || env+=(LINUXCNC_FORCE_REALTIME=1)
        if [ "$ser" != defaults ]; then
            env+=(RTAPI_CPU_NUMBER="$cpu" SBS_TIMER_SLACK_NS=1 SBS_CPU_LATENCY=1)
        fi
        (cd "$work" && env "${env[@]}" "$peer" run -m "$work/modules" halrun -f "$name.hal")
    fi > "$out" 2> "$out.err" || true
}

# find_task TOKEN IMPL: the /proc task directory of the HAL thread `t` in
# the run's own processes.
find_task() {
    local token=$1 impl=$2 proc comm p t c
    if [ "$impl" = ours ]; then
        proc=hal-host comm=hal-t
    else
        proc=rtapi_app comm="rtapi_app:T#0"
    fi
    for p in /proc/[0-9]*; do
        { read -r c < "$p/comm"; } 2>/dev/null || continue
        [ "$c" = "$proc" ] || continue
        { tr '\0' '\n' < "$p/environ" | grep -qx "SBS_RUN_TOKEN=$token"; } 2>/dev/null || continue
        for t in "$p"/task/[0-9]*; do
            { read -r c < "$t/comm"; } 2>/dev/null || continue
            if [ "$c" = "$comm" ]; then
                echo "$t"
                return
            fi
        done
    done
}

# thread_cpu TOKEN IMPL: CPU ns per 1 ms cycle charged to the run's thread,
# read over one second once it has been running for half a second.
thread_cpu() {
    local tries=0 task="" c0 c1 w0 w1
    while [ -z "$task" ] && [ $tries -lt 50 ]; do
        sleep 0.1
        task=$(find_task "$1" "$2")
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

# samples_of FILE IMPL [SKIP]: the first column of FILE after SKIP lines
# (the first cycles fault pages in and warm caches), in ns: LinuxCNC's
# thread times are TSC ticks.
samples_of() {
    local scale=1
    [ "$2" = ours ] || scale=$(awk -v hz="$tsc_hz" 'BEGIN { printf "%.9f", 1e9 / hz }')
    tail -n +"$((${3:-100} + 1))" "$1" |
        awk -v s="$scale" 'NF >= 1 && $1 ~ /^-?[0-9]+$/ { printf "%.1f\n", $1 * s }'
}

median() {
    grep -v '^-*$' | sort -g |
        awk '{ v[NR] = $1 } END { if (NR == 0) print "-"; else printf "%.1f\n", v[int((NR + 1) / 2)] }'
}

loadavg() { cut -d' ' -f1-3 /proc/loadavg; }

cases="sampler-only sum2 and2 sum2-untimed streamer parport"
impls=ours
[ -z "$with_peer" ] || impls="ours lcnc"

# run_series SERIES: every case RUNS times, alternating which side goes first.
run_series() {
    local ser=$1 r=1 c i order token
    mkdir -p "$work/$ser"
    loadavg > "$work/$ser/load-before"
    while [ $r -le "$runs" ]; do
        order=$impls
        [ $((r % 2)) -eq 1 ] || order=$(echo "$impls" | awk '{ for (i = NF; i > 0; i--) printf "%s ", $i }')
        for c in $cases latency; do
            for i in $order; do
                [ "$i" = lcnc ] && [ "$c" = sum2-untimed ] && continue
                token=$$-$ser-$r-$c-$i
                if [ "$c" = sampler-only ]; then
                    run_hal "$i" "$ser" "$c" "$token" &
                    thread_cpu "$token" "$i" >> "$work/$ser/$i-cpu.runs"
                    wait $!
                else
                    run_hal "$i" "$ser" "$c" "$token"
                fi
                if [ "$c" = latency ]; then
                    samples_of "$work/$ser/$i-$c.out" ours |
                        awk '{ d = $1 - 1000000; print (d < 0 ? -d : d) }' >> "$work/$ser/$i-latency.all"
                else
                    samples_of "$work/$ser/$i-$c.out" "$i" | median >> "$work/$ser/$i-$c.runs"
                fi
            done
        done
        r=$((r + 1))
    done
    loadavg > "$work/$ser/load-after"
}

get() { if [ -f "$work/$1/$2-$3.runs" ]; then median < "$work/$1/$2-$3.runs"; else echo -; fi; }
per_funct() {
    { [ "$1" = - ] || [ "$2" = - ]; } && { echo -; return; }
    awk -v a="$1" -v b="$2" 'BEGIN { printf "%.1f", (a - b) / 100 }'
}
difference() {
    { [ "$1" = - ] || [ "$2" = - ]; } && { echo -; return; }
    awk -v a="$1" -v b="$2" 'BEGIN { printf "%.0f", a - b }'
}
ratio() {
    { [ "$1" = - ] || [ "$2" = - ]; } && { echo -; return; }
    awk -v a="$1" -v b="$2" 'BEGIN { if (b <= 0) print "-"; else printf "%.2f", a / b }'
}
# percentile SERIES IMPL P: the P-th percentile (0..1, 1 = max) of latencies.
percentile() {
    local f=$work/$1/$2-latency.all
    [ -s "$f" ] || { echo -; return; }
    sort -n "$f" | awk -v p="$3" '{ v[NR] = $1 }
        END { i = int(NR * p + 0.999999); if (i < 1) i = 1; if (i > NR) i = NR; print v[i] }'
}
row() { printf '%-24s %10s %10s %8s\n' "$1" "$2" "$3" "$(ratio "$2" "$3")"; }

report_series() {
    local ser=$1 c so sl p
    echo
    echo "== series: $ser ($([ -n "$realtime" ] && echo realtime: SCHED_FIFO on both || echo without realtime on both))"
    case $ser in
    defaults) echo "   each side's own settings: LinuxCNC pins its thread to the last CPU and keeps the 50 us timer slack;"
        echo "   ours $([ -n "$realtime" ] && echo "pins to the last CPU" || echo "floats, asks for a short slice"), sets 1 ns slack and holds a zero latency request where it may" ;;
    matched) echo "   both alike: threads on CPU $cpu, timer slack 1 ns, zero CPU latency request, no short slice" ;;
    esac
    echo "   load average before: $(cat "$work/$ser/load-before"), after: $(cat "$work/$ser/load-after")"
    echo "thread time of a 1 ms thread, median of $runs alternating runs of $samples cycles (ns;"
    echo "LinuxCNC's TSC ticks converted at $(awk -v h="$tsc_hz" 'BEGIN { printf "%.4f", h / 1e9 }') ticks/ns)"
    printf '%-24s %10s %10s %8s\n' case ours linuxcnc ratio
    for c in $cases; do
        row "$c" "$(get "$ser" ours "$c")" "$(get "$ser" lcnc "$c")"
    done
    echo "per function, (case - sampler-only) / 100 (ns)"
    so=$(get "$ser" ours sampler-only) sl=$(get "$ser" lcnc sampler-only)
    for c in sum2 and2 sum2-untimed; do
        row "$c" "$(per_funct "$(get "$ser" ours "$c")" "$so")" "$(per_funct "$(get "$ser" lcnc "$c")" "$sl")"
    done
    echo "streamer function, streamer - sampler-only (ns)"
    row streamer "$(difference "$(get "$ser" ours streamer)" "$so")" \
        "$(difference "$(get "$ser" lcnc streamer)" "$sl")"
    echo "our hal_parport driver, read + write on its simulated port, parport - sampler-only (ns)"
    row parport-read+write "$(difference "$(get "$ser" ours parport)" "$so")" \
        "$(difference "$(get "$ser" lcnc parport)" "$sl")"
    echo "CPU charged to the sampler-only thread per cycle, median of $runs runs (ns)"
    row sampler-thread "$(get "$ser" ours cpu)" "$(get "$ser" lcnc cpu)"
    echo "1 ms interval error |timedelta.out - 1 ms| over $runs x $lat_samples cycles (ns on both sides)"
    for p in p50:0.5 p99:0.99 p99.9:0.999 max:1; do
        row "${p%%:*}" "$(percentile "$ser" ours "${p#*:}")" "$(percentile "$ser" lcnc "${p#*:}")"
    done
}

# unit_check: the burst check (see the header), in the matched setting
# (run_hal treats every series but defaults as matched).
unit_check() {
    local i token out base peak
    mkdir -p "$work/check"
    echo
    echo "== unit check: 1500 us bursts at SCHED_FIFO 99 on CPU $cpu during sum2 x400 (load $(loadavg))"
    printf '%-10s %14s %8s %14s %10s\n' side median-ns hits median-excess excess/burst
    for i in $impls; do
        token=$$-check-$i
        "$work/burst" "$cpu" 1500 3001 1400 &
        local burst_pid=$!
        run_hal "$i" check burst-check "$token"
        kill "$burst_pid" 2>/dev/null || true
        wait "$burst_pid" 2>/dev/null || true
        out=$work/check/$i-burst-check.out
        base=$(samples_of "$out" "$i" | median)
        # The cycles a burst landed in: more than half a burst over the median.
        hit=$(samples_of "$out" "$i" | awk -v b="$base" '$1 - b > 750000 { print $1 - b }' | median)
        printf '%-10s %14s %8s %14s %10s\n' "$i" "$base" \
            "$(samples_of "$out" "$i" | awk -v b="$base" '$1 - b > 750000' | wc -l)" "$hit" \
            "$([ "$hit" = - ] && echo - || awk -v h="$hit" 'BEGIN { printf "%.3f", h / 1500000 }')"
    done
    echo "(near 1.00 on both sides: a burst is counted once, in ns; LinuxCNC's raw"
    echo " ticks would give $(awk -v h="$tsc_hz" 'BEGIN { printf "%.2f", h / 1e9 }'))"
}

echo "side-by-side: ours from $ours$([ -n "$with_peer" ] && echo ", LinuxCNC 2.9 from $("$peer" prefix)")"
echo "TSC rate measured against CLOCK_MONOTONIC_RAW: $tsc_hz Hz; $(nproc) CPUs; kernel $(uname -r)"
echo "units: ours reports ns; LinuxCNC 2.9 reports thread and function times in TSC ticks (converted below)"
for ser in defaults matched; do
    [ "$series" = both ] || [ "$series" = "$ser" ] || continue
    run_series "$ser"
done
[ -z "$check" ] || unit_check
for ser in defaults matched; do
    [ "$series" = both ] || [ "$series" = "$ser" ] || continue
    report_series "$ser"
done

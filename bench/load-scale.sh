#!/usr/bin/env bash
# How loading grows with the size of a configuration: for each N, one
# halrun file loads N and2 instances, adds their functions to a thread
# (N addf lines), chains them with N-1 nets, lists every pin with
# `show pin`, and exits; the script prints each phase's wall time, so
# growth faster than the work shows as a ratio above 4 between N and 4N.
#
#   bench/load-scale.sh [-b OUR_BIN_DIR] [N ...]
#
# Default N: 1000 4000 16000 64000, and 25000 (100,000 pins: and2 has
# three pins and its function a .time pin). OUR_BIN_DIR as in
# side-by-side.sh (default target/release, built if halrun is missing).
# The segment is sized for the largest N (HAL_SHM_SIZE; about 5.2 kB per
# instance). Phases are timed by `loadusr -w` of a one-line script that
# appends the time; each stamp costs a fork and exec (about a ms).
set -euo pipefail

ours=""
while getopts b:h opt; do
    case $opt in
    b) ours=$OPTARG ;;
    *) sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
    esac
done
shift $((OPTIND - 1))
sizes=${*:-1000 4000 16000 25000 64000}

top=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "$ours" ]; then
    ours=$top/target/release
    [ -x "$ours/halrun" ] || (cd "$top" && cargo build --release -p hal-tools --bin halrun \
        --bin halcmd --bin hal-host)
fi
ours=$(cd "$ours" && pwd)

work=$(mktemp -d "${TMPDIR:-/tmp}/load-scale.XXXXXX")
trap 'rm -rf "$work"' EXIT
cat > "$work/stamp" <<'EOF'
#!/bin/sh
echo "$1 $(date +%s%N)" >> "$STAMPS"
EOF
chmod +x "$work/stamp"

max=0
for n in $sizes; do [ "$n" -le "$max" ] || max=$n; done
shm=$(( (max * 5300 + 64 * 1024 * 1024) ))

echo "load scaling: N and2 instances (4N pins), N addf, N-1 net, show pin; ours from $ours"
echo "segment $((shm >> 20)) MiB; load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%8s %8s %9s %9s %9s %9s %9s %9s\n' N pins loadrt addf net show exit total
for n in $sizes; do
    f=$work/scale-$n.hal
    {
        echo "loadusr -w ./stamp begin"
        echo "loadrt threads name1=t period1=1000000"
        echo "loadrt and2 count=$n"
        echo "loadusr -w ./stamp loadrt"
        awk -v n="$n" 'BEGIN { for (i = 0; i < n; i++) printf "addf and2.%d t\n", i }'
        echo "loadusr -w ./stamp addf"
        awk -v n="$n" 'BEGIN { for (i = 1; i < n; i++) printf "net c%d and2.%d.out => and2.%d.in0\n", i, i - 1, i }'
        echo "loadusr -w ./stamp net"
        echo "show pin"
        echo "loadusr -w ./stamp show"
    } > "$f"
    stamps=$work/stamps-$n
    : > "$stamps"
    t0=$(date +%s%N)
    (cd "$work" && STAMPS=$stamps HAL_INSTANCE="scale-$$-$n" HAL_SHM_SIZE=$shm HAL_NO_REALTIME=1 \
        PATH="$ours:$PATH" "$ours/halrun" -f "$f") > "$work/out-$n" 2> "$work/err-$n" || {
        echo "N=$n failed:"; tail -5 "$work/err-$n"; continue; }
    t1=$(date +%s%N)
    pins=$(grep -c ' and2\.' "$work/out-$n" || true)
    awk -v n="$n" -v pins="$pins" -v t0="$t0" -v t1="$t1" '
        { t[$1] = $2 }
        END {
            printf "%8d %8d %8.2fs %8.2fs %8.2fs %8.2fs %8.2fs %8.2fs\n", n, pins,
                (t["loadrt"] - t["begin"]) / 1e9, (t["addf"] - t["loadrt"]) / 1e9,
                (t["net"] - t["addf"]) / 1e9, (t["show"] - t["net"]) / 1e9,
                (t1 - t["show"]) / 1e9, (t1 - t0) / 1e9
        }' "$stamps"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"

#!/bin/sh
# Waits until each pin named reads the value given after it, or, with
# the value written !VALUE, anything but that value (at most 30 s):
#   loadusr -w sh pins-wait.sh lcec.0.io.lamp-on TRUE lcec.0.x.enc-count !0
# What is shown next then does not depend on how fast the threads ran.
i=0
while [ $i -lt 600 ]; do
    done_all=1
    set_args="$*"
    set -- $set_args
    while [ $# -ge 2 ]; do
        got="$(halcmd getp "$1")"
        case "$2" in
            !*) [ "$got" != "${2#!}" ] || done_all=0 ;;
            *) [ "$got" = "$2" ] || done_all=0 ;;
        esac
        shift 2
    done
    set -- $set_args
    [ $done_all = 1 ] && exit 0
    sleep 0.05
    i=$((i + 1))
done
echo "pins-wait.sh: the pins did not reach their values within 30 s: $*" >&2
exit 1

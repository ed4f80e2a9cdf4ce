#!/bin/sh
# Waits until every pin named on the command line reads 0: given the
# encoders' velocity pins, until the motors stand still (the canonical
# encoder reports 0 once no count has come for vel-timeout, 0.5 s). From
# then on nothing moves until the next command, so what is sampled next
# does not depend on when that command arrives.
#   loadusr -w sh servo-card-settle.sh motenc.0.enc-00-velocity ...
i=0
while [ $i -lt 600 ]; do
    moving=0
    for pin in "$@"; do
        [ "$(halcmd getp "$pin")" = "0" ] || moving=1
    done
    [ $moving = 0 ] && exit 0
    sleep 0.05
    i=$((i + 1))
done
echo "servo-card-settle.sh: the motors did not stop within 30 s" >&2
exit 1

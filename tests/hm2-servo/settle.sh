#!/bin/sh
# Waits until the three motors stand still: every encoder's velocity is
# 0, which hostmot2 reports once no count has come for vel-timeout
# (0.5 s). From then on nothing moves until the next command, so what is
# sampled next does not depend on when that command arrives.
i=0
while [ $i -lt 600 ]; do
    moving=0
    for e in 00 01 02; do
        [ "$(halcmd getp hm2_6i25.0.encoder.$e.velocity)" = "0" ] || moving=1
    done
    [ $moving = 0 ] && exit 0
    sleep 0.05
    i=$((i + 1))
done
echo "settle.sh: the motors did not stop within 30 s" >&2
exit 1

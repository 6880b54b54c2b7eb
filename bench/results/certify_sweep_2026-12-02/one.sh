#!/bin/bash
# run one flipflux command, print rc, cpu (user+sys), wall, stderr, and short stdout
export FLIPFLUX_PLUGIN_DIR=/work/main/build/release/plugins
/usr/bin/time -f "TIME user=%U sys=%S wall=%e rc=%x" -o /tmp/certsweep/.t timeout 120 /work/main/build/release/flipflux "$@" > /tmp/certsweep/.o 2> /tmp/certsweep/.e
echo "CMD: flipflux $*"; cat /tmp/certsweep/.t; echo "STDERR:"; cat /tmp/certsweep/.e; echo "STDOUT:"; grep -E '"seconds"|"value"|proven' /tmp/certsweep/.o

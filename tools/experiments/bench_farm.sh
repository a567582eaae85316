#!/bin/bash
# throughput of the farm against workers, side by side, two rounds
# run from the repository root with the venv's python on PATH (or PY=...); writes /tmp/farm-bench/
PY=${PY:-python}
ARGS="many_lights --width 160 --height 90 --frames 0-47 --warmup-frames 8"
for round in 1 2; do
  for cfg in "inproc|" "w1|--workers 1" "w2|--workers 2" "w2c8|--workers 2 --chunk-size 8"; do
    name=${cfg%%|*}; opts=${cfg#*|}
    rm -rf /tmp/farm-bench/$name
    echo "== round $round $name ($opts) load: $(cut -d' ' -f1-3 /proc/loadavg)"
    t0=$(date +%s.%N)
    $PY -m restircl render $ARGS $opts --out /tmp/farm-bench/$name 2>/dev/null | grep -E "wrote|chunk "
    t1=$(date +%s.%N)
    echo "wall $(echo "$t1 - $t0" | bc) s"
  done
done

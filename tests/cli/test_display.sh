#!/bin/sh
# test_display.sh — --display-server against a fake tev (tests/cli/fake_tev.py,
# started and stopped here by its pid), which rebuilds the image from tev's
# packets: it is created once with R, G, B at the render's size, every tile
# updated, and its last image equals the EXR's pixels bit for bit; a viewer
# that closes mid-render, or none at all, is one warning and changes nothing
# in the image. TAP output.
. tests/tap.sh
R="--width 96 --height 80 --spp 64 --wave 4096 --quiet --env 0"
fake=""
# start_fake OUT [--close-after N]: the fake viewer in the background, its port in $port
start_fake() {
    out=$1
    shift
    rm -f "$T/port"
    python3 tests/cli/fake_tev.py --port-file "$T/port" --out "$out" "$@" &
    fake=$!
    i=0
    while [ ! -s "$T/port" ] && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
    port=$(cat "$T/port" 2> /dev/null)
}
# stop_fake: waits up to 10 s for it to end by itself (it does when the
# connection closes), then ends it by its pid
stop_fake() {
    i=0
    while kill -0 "$fake" 2> /dev/null && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
    kill "$fake" 2> /dev/null
    wait "$fake" 2> /dev/null
    fake=""
}
trap '[ -n "$fake" ] && kill "$fake" 2> /dev/null; rm -rf "$T"' EXIT

expect "--display-server without a port exits 2" 2 "^strata: error: --display-server localhost: expected HOST:PORT" \
    "$S" render $R --display-server localhost -o "$T/o.exr"
expect "--display-server with port 0 exits 2" 2 "^strata: error: --display-server localhost:0: expected HOST:PORT" \
    "$S" render $R --display-server localhost:0 -o "$T/o.exr"
expect "bench --display-server exits 2" 2 "^strata: error: --display-server: only .strata render." \
    "$S" bench $R --display-server localhost:14158

"$S" render $R -o "$T/alone.exr" 2> /dev/null

start_fake "$T/tev"
"$S" render $R --display-server "127.0.0.1:$port" -o "$T/shown.exr" 2> "$T/err"
status=$?
stop_fake
check "a render shown in the viewer succeeds without a word" '[ $status -eq 0 ] && [ ! -s "$T/err" ]' "(status $status: $(head -c 300 "$T/err"))"
check "the viewer got CreateImage first, once, with R, G, B at the render's size" \
    '[ "$(head -n 1 "$T/tev.log")" = "create $T/shown.exr 96x80 R,G,B" ] && [ "$(grep -c "^create" "$T/tev.log")" = 1 ]' \
    "($(head -n 3 "$T/tev.log"))"
check "then UpdateImageV3 packets of 64-pixel tiles with R, G, B" \
    'grep -q "^update $T/shown.exr 64,64 32x16 R,G,B$" "$T/tev.log" && ! grep -v "^create\|^update" "$T/tev.log"' \
    "($(grep -v "^update" "$T/tev.log" | head -n 3))"
"$S" diff "$T/shown.exr" "$T/tev.exr" > "$T/diff" 2>&1
check "the viewer's last image is the EXR's, bit for bit" 'grep -q "^rmse 0$" "$T/diff" && grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"
"$S" diff "$T/shown.exr" "$T/alone.exr" > "$T/diff" 2>&1
check "a render shown equals one not shown" 'grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"
echo "# the viewer received $(grep -c "^update" "$T/tev.log") tile updates ($(($(grep -c "^update" "$T/tev.log") / 4)) looks at 4 tiles)"

# it closes as soon as the image is announced, before the render has sent a
# tile, so that the render's sends after it must fail however fast it is
start_fake "$T/closing" --close-after 1
"$S" render $R --display-server "127.0.0.1:$port" -o "$T/closed.exr" 2> "$T/err"
status=$?
stop_fake
check "a viewer that closes mid-render: the render succeeds" '[ $status -eq 0 ] && [ -s "$T/closed.exr" ]' "(status $status)"
check "... with one warning naming the display server" \
    '[ "$(grep -c "^strata: warning: --display-server 127.0.0.1:$port: " "$T/err")" = 1 ] && [ "$(wc -l < "$T/err")" = 1 ]' "($(cat "$T/err"))"
"$S" diff "$T/closed.exr" "$T/alone.exr" > "$T/diff" 2>&1
check "... and the same image" 'grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"

# the port the closed viewer listened on: nothing there now
"$S" render $R --display-server "127.0.0.1:$port" -o "$T/none.exr" 2> "$T/err"
status=$?
check "no viewer: the render succeeds with one warning" \
    '[ $status -eq 0 ] && [ "$(wc -l < "$T/err")" = 1 ] && grep -q "^strata: warning: --display-server 127.0.0.1:$port: Connection refused" "$T/err"' \
    "(status $status: $(cat "$T/err"))"
"$S" diff "$T/none.exr" "$T/alone.exr" > "$T/diff" 2>&1
check "... and the same image" 'grep -q "^max_abs 0$" "$T/diff"' "($(cat "$T/diff"))"
echo "1..$n"

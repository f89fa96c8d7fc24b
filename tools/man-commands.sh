#!/bin/sh
# man-commands.sh STRATA COMMAND... — a help2man include file: tools/strata.h2m, then a
# COMMANDS section holding each subcommand's --help text verbatim (roff-escaped), so the man
# page says exactly what the help texts say.
strata=$1
shift
cat tools/strata.h2m
echo '[COMMANDS]'
for c in "$@"; do
    echo ".SS strata $c"
    echo ".nf"
    "$strata" "$c" --help | sed -e 's/\\/\\e/g' -e "s/^[.']/\\\\\\&&/"
    echo ".fi"
done

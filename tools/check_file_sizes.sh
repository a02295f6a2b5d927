#!/bin/sh
# make lint's file-size limit (issue 32): every C++ and Python source file
# under the given folders with more than LIMIT lines is listed with its line
# count, and the check fails. A file that long holds more than one concept:
# split it by concept (docs in the file's header comment say which).
# POSIX sh, find, wc and sort only: runs in a fresh clone with Debian's base.
# Usage: tools/check_file_sizes.sh LIMIT DIR...
set -eu
limit=$1
shift
over=0
for f in $(find "$@" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.c' -o -name '*.py' \) | sort); do
    n=$(wc -l < "$f")
    if [ "$n" -gt "$limit" ]; then
        echo "$f: $n lines (the limit is $limit)" >&2
        over=$((over + 1))
    fi
done
if [ "$over" -gt 0 ]; then
    echo "file size: $over file(s) above $limit lines; split each by concept" >&2
    exit 1
fi

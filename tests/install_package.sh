#!/usr/bin/env bash
# rtt as a library (bash install_package.sh <rtt> <source-dir>): installs the
# build into a temporary prefix with `cmake --install`, then builds a small
# program against it out of the tree twice — with find_package(rtt) and with
# pkg-config — and runs both: they trace rays through the installed library.
set -euo pipefail
rtt=${1:?usage: install_package.sh <rtt> <source-dir>}
source_dir=${2:?usage: install_package.sh <rtt> <source-dir>}
build_dir=$(cd "$(dirname "$rtt")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# a sanitizer build's library needs its runtime linked into the program too
sanitize=$(sed -n 's/^RTT_SANITIZE:STRING=//p' "$build_dir/CMakeCache.txt")
user_flags=()
[ -n "$sanitize" ] && user_flags=(-fsanitize="$sanitize")

cmake --install "$build_dir" --prefix "$work/prefix" >"$work/install.log" 2>&1 || { cat "$work/install.log"; exit 1; }
for f in include/rtt/rtt.h include/rtt/engine.h lib/librtt.so lib/cmake/rtt/rttConfig.cmake lib/pkgconfig/rtt.pc; do
    [ -e "$work/prefix/$f" ] || { echo "install_package: $f not installed"; exit 1; }
done
if [ -n "$(find "$work/prefix/include" -name '*.h' ! -path '*/include/rtt/*')" ]; then
    echo "install_package: headers outside include/rtt/ were installed"; exit 1
fi

# find_package(rtt) -> rtt::rtt
cmake -S "$source_dir/tests/package" -B "$work/user" -DCMAKE_PREFIX_PATH="$work/prefix" \
    -DCMAKE_C_FLAGS="${user_flags[*]:-}" >"$work/user.log" 2>&1 ||
    { cat "$work/user.log"; exit 1; }
cmake --build "$work/user" >>"$work/user.log" 2>&1 || { cat "$work/user.log"; exit 1; }
LD_LIBRARY_PATH="$work/prefix/lib" "$work/user/trace_two_triangles"

# pkg-config --cflags --libs rtt
export PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig"
# shellcheck disable=SC2046
cc -std=c11 -Wall -Wextra -Werror "${user_flags[@]}" -o "$work/trace_pc" "$source_dir/tests/package/trace_two_triangles.c" \
    $(pkg-config --cflags --libs rtt) -lm
LD_LIBRARY_PATH="$work/prefix/lib" "$work/trace_pc"
echo "install_package: find_package(rtt) and pkg-config builds trace through the installed library"

#!/usr/bin/env bash
# `rtt CMD --help` against CMD's option table (`rtt CMD --list-options`, one
# row a line: NAME SHORT VALUE, "-" for none): every row has its own help
# line with text, and every option the help names anywhere (usage lines,
# descriptions, other options' text) is a row of the table.  So an option
# added to the table without help, or named in the help without a row,
# fails here.
set -u
rtt="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() {
    echo "FAIL: rtt $command: $*"
    failures=$((failures + 1))
}

for command in render bake info triangles trace conform compare bench rays; do
    if ! "$rtt" "$command" --list-options >"$work/list" 2>"$work/err"; then
        fail "--list-options failed: $(cat "$work/err")"
        continue
    fi
    "$rtt" "$command" --help >"$work/help" 2>&1 || fail "--help exited non-zero"
    [ -s "$work/list" ] || fail "--list-options lists no option"

    # table -> help: "  -o, --output FILE   text" or "      --tile N   text", the
    # text on the same line or (a long spelling) indented on the next
    while read -r name short value; do
        spelling="$name"
        [ "$value" != - ] && spelling="$name $value"
        if [ "$short" != - ]; then spelling="$short, $spelling"; else spelling="    $spelling"; fi
        if ! awk -v s="  $spelling" '
                found && match($0, /^ +[^ ]/) && RLENGTH > 20 { ok = 1; exit }
                found { exit }
                index($0, s) == 1 { rest = substr($0, length(s) + 1)
                                    if (rest ~ /^  +[^ ]/) { ok = 1; exit }
                                    if (rest == "") found = 1 }
                END { exit !ok }' "$work/help"; then
            fail "table row $name has no help line (\"  $spelling  text\")"
        fi
    done <"$work/list"

    # help -> table: every option named in the help is a row (or --help/-h)
    grep -oE -- '(^|[^[:alnum:]_$-])--?[a-z][a-z0-9-]*' "$work/help" | sed -E 's/^[^-]*//' | sort -u >"$work/named"
    while read -r option; do
        case "$option" in --help | -h) continue ;; esac
        if ! awk -v o="$option" '$1 == o || $2 == o { found = 1 } END { exit !found }' "$work/list"; then
            fail "the help names $option, which is no option of the table"
        fi
    done <"$work/named"
done

if [ "$failures" -ne 0 ]; then
    echo "$failures help/table mismatches"
    exit 1
fi
echo "every command's help matches its option table"

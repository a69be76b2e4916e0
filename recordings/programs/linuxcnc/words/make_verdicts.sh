#!/bin/sh
# What LinuxCNC's own interpreter says of a line that writes a word twice or two M codes at once, as
# reference for tests/readers/linuxcnc_words.rs: `rs274` (the standalone RS274NGC interpreter of
# Debian 12's linuxcnc-uspace 2.9.0~pre1) runs each case as the third line of a program
# (`G21 G90`, `T1 M6`, the case, `M2`) and its first message, or `ok`, is written beside the case in
# verdicts.tsv. The cases: every letter written twice in a G1 block, and every pair of the M codes
# LinuxCNC reads, each code with itself too, without the words some of them need: rs274 says two
# codes of one modal group before it asks for them.
# Where linuxcnc-uspace will not install, rs274 runs from the package unpacked, as
# ../parameters/make_canon.sh says: RS274=<dir>/usr/bin/rs274 with LD_LIBRARY_PATH set.
set -eu
cd "$(dirname "$0")"
RS274=${RS274:-rs274}
tmp=$(mktemp -d)
printf 'T1 P1 Z0 D10 ;\n' > "$tmp/t.tbl"
verdict() {
    printf 'G21 G90\nT1 M6\n%s\nM2\n' "$1" > "$tmp/p.ngc"
    msg=$("$RS274" -t "$tmp/t.tbl" -g "$tmp/p.ngc" "$tmp/out.canon" < /dev/null 2>&1 | grep -v '^executing$' | grep -v '^$' | head -1 || true)
    printf '%s\t%s\n' "$1" "${msg:-ok}"
}
{
    for l in A B C D E F H I J K L P Q R S T X Y Z; do
        verdict "G1 F100 ${l}1 ${l}2"
    done
    codes="0 1 2 3 4 5 6 7 8 9 19 30 48 49 50 51 52 53 60 61 62 63 64 65 66 67 68 70 71 72 73 100 150 199"
    for a in $codes; do
        for b in $codes; do
            [ "$a" -gt "$b" ] && continue
            verdict "M$a M$b"
        done
    done
} > verdicts.tsv
rm -r "$tmp"
